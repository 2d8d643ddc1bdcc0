// veil: render, inspect and (later) voxelize volumetric and transparent scenes.
#include "app/commands.h"
#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"

#include <cstdio>
#include <exception>
#include <new>
#include <string>

namespace {

// One line, as README promises for every error: CLI11 messages may hold newlines, and
// arguments echoed in messages may hold any bytes.
int fail(const std::string& message) {
    std::string line = message;
    for (std::size_t i = line.find('\n'); i != std::string::npos; i = line.find('\n', i))
        line.replace(i, 1, "; ");
    std::fprintf(stderr, "veil: error: %s\n", veil::printable(line, 1000).c_str());
    return 1;
}

} // namespace

int main(int argc, char** argv) {
    // An interrupted write leaves no temporary behind (base/atomic_file.h).
    veil::installTemporaryFileCleanup();
    CLI::App app{"Veil: volumetric and transparent real-time rendering"};
    app.set_version_flag("--version", std::string("veil ") + VEIL_VERSION);
    app.require_subcommand(1);
    veil::app::addRenderCommand(app);
    veil::app::addInfoCommand(app);
    veil::app::addViewCommand(app);
    veil::app::addVoxelizeCommand(app);
    veil::app::addTechniquesCommand(app);
    veil::app::addCompareCommand(app);
    veil::app::addRegressCommand(app);
    // CLI11 would call a misspelt command an unexpected argument, after "a subcommand is
    // required"; the user wants to hear which word was not understood.
    if (argc > 1 && argv[1][0] != '-') {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands({})) {
            known = known || sub->check_name(argv[1]);
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!known)
            return fail("unknown command '" + std::string(argv[1]) + "' (commands: " + names +
                        "; see veil --help)");
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help, --version
        return fail(std::string(e.what()) + " (see veil --help)");
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
