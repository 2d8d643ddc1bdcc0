// veil: render, inspect and (later) voxelize volumetric and transparent scenes.
#include "app/commands.h"
#include "base/error.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"Veil: volumetric and transparent real-time rendering"};
    app.require_subcommand(1);
    veil::app::addRenderCommand(app);
    veil::app::addInfoCommand(app);
    veil::app::addViewCommand(app);
    veil::app::addVoxelizeCommand(app);
    veil::app::addTechniquesCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const veil::Error& e) {
        std::fprintf(stderr, "veil: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "veil: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
