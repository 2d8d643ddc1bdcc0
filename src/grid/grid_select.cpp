#include "grid/grid_select.h"

#include "base/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace veil::vdb {

std::string gridTypeName(const openvdb::GridBase& grid) { return grid.valueType(); }

std::string listGrids(const openvdb::GridPtrVec& grids) {
    std::string s;
    for (std::size_t i = 0; i < grids.size(); ++i)
        s += fmt::format("{}{} '{}' ({})", i ? ", " : "", i, grids[i]->getName(),
                         gridTypeName(*grids[i]));
    return s.empty() ? std::string("none") : s;
}

SelectedGrid selectGrid(const openvdb::GridPtrVec& grids, const std::filesystem::path& file,
                        const std::string& selector,
                        const std::function<bool(const openvdb::GridBase&)>& accept,
                        const std::string& wanted) {
    const std::string name = file.string();
    VEIL_CHECK(!grids.empty(), "'{}' holds no grids", name);
    std::size_t index = grids.size();
    if (selector.empty()) {
        for (std::size_t i = 0; i < grids.size() && index == grids.size(); ++i)
            if (accept(*grids[i])) index = i;
        VEIL_CHECK(index < grids.size(), "'{}': none of its grids is {} (grids: {})", name, wanted,
                   listGrids(grids));
    } else {
        for (std::size_t i = 0; i < grids.size() && index == grids.size(); ++i)
            if (grids[i]->getName() == selector) index = i;
        const bool digits =
            selector.size() <= 9 && std::all_of(selector.begin(), selector.end(),
                                                [](unsigned char c) { return std::isdigit(c); });
        if (index == grids.size() && digits) {
            index = std::stoul(selector);
            VEIL_CHECK(index < grids.size(), "'{}' has no grid {} ({} grids: {})", name, selector,
                       grids.size(), listGrids(grids));
        }
        VEIL_CHECK(index < grids.size(), "'{}' has no grid named '{}' (grids: {})", name, selector,
                   listGrids(grids));
        VEIL_CHECK(accept(*grids[index]), "'{}': grid {} '{}' is {}, not {}", name, index,
                   grids[index]->getName(), gridTypeName(*grids[index]), wanted);
    }
    return {grids[index], index};
}

} // namespace veil::vdb
