#include "viewer/ui/file_dialog.h"

#include "base/text.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>

namespace veil::ui {

namespace fs = std::filesystem;

FileDialog::FileDialog(std::string title, std::vector<std::string> extensions)
    : title_(std::move(title)), extensions_(std::move(extensions)) {}

void FileDialog::open(const fs::path& folder) {
    std::error_code ec;
    folder_ = fs::is_directory(folder, ec) ? fs::absolute(folder) : fs::current_path(ec);
    path_ = folder_.string() + "/";
    open_ = justOpened_ = true;
    list();
}

void FileDialog::list() {
    entries_.clear();
    error_.clear();
    std::error_code ec;
    for (fs::directory_iterator it(folder_, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        const bool folder = it->is_directory(ec);
        const std::string ext = lowerExtension(name);
        if (!folder && std::find(extensions_.begin(), extensions_.end(), ext) == extensions_.end())
            continue;
        entries_.push_back({name, folder});
    }
    if (ec) error_ = "cannot list " + folder_.string() + ": " + ec.message();
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
        return a.folder != b.folder ? a.folder : a.name < b.name;
    });
}

std::optional<fs::path> FileDialog::draw() {
    if (!open_) return std::nullopt;
    if (justOpened_) {
        ImGui::OpenPopup(title_.c_str());
        justOpened_ = false;
    }
    std::optional<fs::path> chosen;
    ImGui::SetNextWindowSize(ImVec2(ImGui::GetFontSize() * 36, ImGui::GetFontSize() * 24),
                             ImGuiCond_Appearing);
    if (ImGui::BeginPopupModal(title_.c_str(), &open_)) {
        ImGui::TextUnformatted(folder_.string().c_str());
        if (ImGui::Button("..")) {
            folder_ = folder_.parent_path();
            list();
        }
        if (!error_.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", error_.c_str());
        ImGui::BeginChild("entries", ImVec2(0, -ImGui::GetFrameHeightWithSpacing() * 2), true);
        for (const Entry& e : entries_) {
            const std::string label = e.folder ? e.name + "/" : e.name;
            if (ImGui::Selectable(label.c_str(), false, ImGuiSelectableFlags_AllowDoubleClick)) {
                if (e.folder) {
                    folder_ /= e.name;
                    path_ = folder_.string() + "/";
                    list();
                    break;
                }
                path_ = (folder_ / e.name).string();
                if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) chosen = path_;
            }
        }
        ImGui::EndChild();
        ImGui::InputText("file", &path_);
        ImGui::SameLine();
        if (ImGui::Button("Open")) chosen = path_;
        if (chosen) {
            open_ = false;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    return chosen;
}

} // namespace veil::ui
