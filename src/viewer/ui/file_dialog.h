// A file dialog of the viewer's own, in Dear ImGui (no native toolkit): a folder listing
// with the entries that end in one of the wanted extensions, a path field, and Open.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::ui {

class FileDialog {
public:
    FileDialog(std::string title, std::vector<std::string> extensions);
    void open(const std::filesystem::path& folder);
    // Draws the dialog while it is open; returns the chosen file once.
    std::optional<std::filesystem::path> draw();
    bool isOpen() const { return open_; }

private:
    void list();
    std::string title_;
    std::vector<std::string> extensions_;
    std::filesystem::path folder_;
    std::string path_, error_;
    struct Entry {
        std::string name;
        bool folder;
    };
    std::vector<Entry> entries_;
    bool open_ = false, justOpened_ = false;
};

} // namespace veil::ui
