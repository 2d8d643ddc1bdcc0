// veil: render, view and voxelize volumetric and transparent scenes, compare images, run image
// regression suites. main() adds the subcommands (commands.h), parses the arguments and turns
// errors into messages and exit statuses (2 for usage errors).
#include "app/commands.h"
#include "app/shared_options.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/suggest.h"
#include "base/text.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

// Exit statuses (README, `veil --help`): 1 for an error while running a command (bad input
// files, a failed render, I/O), 2 for a command line that was not understood.
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

// One line, as README promises for every error: CLI11 messages may hold newlines, and
// arguments echoed in messages may hold any bytes.
int fail(const std::string& message, int status = kExitError) {
    std::string line = message;
    for (std::size_t i = line.find('\n'); i != std::string::npos; i = line.find('\n', i))
        line.replace(i, 1, "; ");
    std::fprintf(stderr, "veil: error: %s\n", veil::printable(line, 1000).c_str());
    return status;
}

std::vector<std::string> optionNames(const CLI::App& command) {
    std::vector<std::string> names;
    for (const CLI::Option* o : command.get_options()) {
        for (const std::string& l : o->get_lnames())
            names.push_back("--" + l);
        for (const std::string& s : o->get_snames())
            names.push_back("-" + s);
    }
    return names;
}

// For the first option word of argv that `command` does not know: " (did you mean
// '--width'?)" when it is near one of the command's options; else the same for an option of
// another command that it is near, naming that command; else the command's options.
std::string suggestOption(const CLI::App& app, const CLI::App& command, int argc, char** argv) {
    const std::vector<std::string> names = optionNames(command);
    for (int i = 2; i < argc; ++i) {
        std::string word = argv[i];
        if (word.size() < 2 || word[0] != '-' || word == "--") continue;
        if (std::isdigit(static_cast<unsigned char>(word[1]))) continue; // a value: -5, -5--1
        word = word.substr(0, word.find('='));
        if (std::find(names.begin(), names.end(), word) != names.end()) continue;
        if (const std::string near = veil::nearestWord(word, names); !near.empty())
            return " (did you mean '" + near + "'?)";
        for (const CLI::App* other : app.get_subcommands({}))
            if (other != &command)
                if (const std::string near = veil::nearestWord(word, optionNames(*other));
                    !near.empty())
                    return " ('" + word + "' is not an option of " + command.get_name() +
                           "; did you mean '" + near + "' of veil " + other->get_name() + "?)";
        std::string list;
        for (const std::string& n : names)
            if (n.rfind("--", 0) == 0 && n != "--help") list += (list.empty() ? "" : " ") + n;
        return " ('" + word + "' is not an option of " + command.get_name() + ": " + list + ")";
    }
    return {};
}

// The first empty value on the command line, described ("--dump ''", "--report=", "argument
// 3 ''"), or empty when there is none. No option or argument of any command means something
// when empty, and CLI11 would store "" as if the option had not been given.
std::string emptyArgument(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word == "--") break;
        if (word.empty()) {
            const std::string previous = argv[i - 1];
            if (i > 1 && previous.size() > 1 && previous[0] == '-')
                return "option " + previous + " needs a value, not ''";
            return "argument " + std::to_string(i) + " is empty ('')";
        }
        if (word.size() > 2 && word.rfind("--", 0) == 0 && word.back() == '=' &&
            word.find('=') == word.size() - 1)
            return "option " + word.substr(0, word.size() - 1) + " needs a value, not ''";
    }
    return {};
}

} // namespace

int main(int argc, char** argv) {
    // An interrupted write leaves no temporary behind (base/atomic_file.h).
    veil::installTemporaryFileCleanup();
    veil::app::setCommandLine(argc, argv);
    CLI::App app{"Veil: volumetric and transparent real-time rendering"};
    app.set_version_flag("--version", "veil " + veil::app::versionWithCommit());
    app.require_subcommand(1);
    app.footer("Exit status: 0 success; 1 error while running (bad input file, failed render, "
               "I/O); 2 usage error (unknown command or option, missing or invalid argument).");
    veil::app::addRenderCommand(app);
    veil::app::addInfoCommand(app);
    veil::app::addViewCommand(app);
    veil::app::addVoxelizeCommand(app);
    veil::app::addTechniquesCommand(app);
    veil::app::addCompareCommand(app);
    veil::app::addRegressCommand(app);
    veil::app::addExportCommand(app);
    // CLI11 would call a misspelt command an unexpected argument, after "a subcommand is
    // required"; the user wants to hear which word was not understood.
    if (argc > 1 && argv[1][0] != '-') {
        std::string names;
        std::vector<std::string> list;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands({})) {
            known = known || sub->check_name(argv[1]);
            names += (names.empty() ? "" : ", ") + sub->get_name();
            list.push_back(sub->get_name());
        }
        const std::string near = veil::nearestWord(argv[1], list);
        if (!known)
            return fail("unknown command '" + std::string(argv[1]) + "'" +
                            (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                            " (commands: " + names + "; see veil --help)",
                        kExitUsage);
    }
    if (const std::string empty = emptyArgument(argc, argv); !empty.empty())
        return fail(empty + (argc > 1 && argv[1][0] != '-'
                                 ? " (see veil " + std::string(argv[1]) + " --help)"
                                 : std::string(" (see veil --help)")),
                    kExitUsage);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help, --version
        std::string hint;
        const bool named = argc > 1 && argv[1][0] != '-';
        if (named)
            for (const CLI::App* sub : app.get_subcommands({}))
                if (sub->check_name(argv[1])) hint = suggestOption(app, *sub, argc, argv);
        return fail(std::string(e.what()) + hint +
                        (named ? " (see veil " + std::string(argv[1]) + " --help)"
                               : std::string(" (see veil --help)")),
                    kExitUsage);
    } catch (const veil::Error& e) {
        return fail(e.what());
    } catch (const std::bad_alloc&) {
        return fail("out of memory (try a smaller grid, image or scene)");
    } catch (const std::exception& e) {
        return fail(e.what());
    } catch (...) {
        return fail("unexpected exception (not a std::exception)");
    }
    return 0;
}
