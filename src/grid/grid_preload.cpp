// Thread-local scopes of grids read ahead (grid_preload.h).
#include "grid/grid_preload.h"

namespace veil::volume {

namespace {
thread_local const std::vector<PreloadedGrid>* tCurrent = nullptr;
}

PreloadedGridScope::PreloadedGridScope(const std::vector<PreloadedGrid>& grids)
    : previous_(tCurrent) {
    tCurrent = &grids;
}

PreloadedGridScope::~PreloadedGridScope() { tCurrent = previous_; }

openvdb::FloatGrid::Ptr findPreloadedGridIn(const std::vector<PreloadedGrid>& grids,
                                            const std::filesystem::path& path,
                                            const std::string& grid) {
    for (const PreloadedGrid& g : grids)
        if (g.grid == grid && g.path == path) return g.value;
    return nullptr;
}

openvdb::FloatGrid::Ptr findPreloadedGrid(const std::filesystem::path& path,
                                          const std::string& grid) {
    return tCurrent ? findPreloadedGridIn(*tCurrent, path, grid) : nullptr;
}

std::shared_ptr<const GridConversion> findPreconverted(const std::filesystem::path& path,
                                                       const std::string& grid,
                                                       const GpuVolumeOptions& options, int max3D) {
    if (!tCurrent) return nullptr;
    for (const PreloadedGrid& g : *tCurrent)
        if (g.converted && g.channel.empty() && g.grid == grid && g.path == path &&
            g.max3D == max3D && g.options.budgetBytes == options.budgetBytes &&
            g.options.refuseOverBudget == options.refuseOverBudget &&
            g.options.denseVoxelLimit == options.denseVoxelLimit &&
            g.options.neighbourhood == options.neighbourhood)
            return g.converted;
    return nullptr;
}

} // namespace veil::volume
