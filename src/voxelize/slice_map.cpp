#include "voxelize/slice_map.h"

#include "base/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace veil::voxelize {

void SliceMap::allocate() {
    VEIL_CHECK(width > 0 && height > 0 && slices > 0, "slice map size {}x{}x{} must be positive",
               width, height, slices);
    words.assign(static_cast<std::size_t>(width) * height * wordsPerColumn(), 0u);
}

bool SliceMap::get(int x, int y, int s) const {
    const std::uint32_t w = words[columnIndex(x, y) * wordsPerColumn() + s / 32];
    return (w >> (s % 32)) & 1u;
}

void SliceMap::set(int x, int y, int s) {
    words[columnIndex(x, y) * wordsPerColumn() + s / 32] |= 1u << (s % 32);
}

std::uint64_t SliceMap::countSet() const {
    std::uint64_t n = 0;
    for (std::uint32_t w : words)
        n += std::popcount(w);
    return n;
}

double SliceMap::depthToSliceCoord(double d) const {
    if (!perspective) return d;
    // Eye depth from window depth of a glm::perspective projection, then linear in near..far.
    const double n = nearPlane, f = farPlane, z = 2.0 * d - 1.0;
    const double eye = 2.0 * n * f / (f + n - z * (f - n));
    return (eye - n) / (f - n);
}

double SliceMap::sliceCoordToDepth(double t) const {
    if (!perspective) return t;
    const double n = nearPlane, f = farPlane, eye = n + t * (f - n);
    const double z = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * eye);
    return 0.5 * z + 0.5;
}

void SliceMap::columnRange(int x, int y, double& t0, double& t1) const {
    if (!local()) {
        t0 = 0.0;
        t1 = 1.0;
        return;
    }
    const std::size_t c = columnIndex(x, y);
    t0 = nearDepth[c];
    t1 = std::max(static_cast<double>(farDepth[c]), t0 + 1e-7);
}

bool SliceMap::locate(const glm::dvec3& world, int& x, int& y, int& s) const {
    const glm::dvec4 clip = viewProj * glm::dvec4(world, 1.0);
    if (clip.w <= 0.0) return false;
    const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
    const double fx = (ndc.x * 0.5 + 0.5) * width, fy = (ndc.y * 0.5 + 0.5) * height;
    if (fx < 0.0 || fy < 0.0 || fx >= width || fy >= height) return false;
    x = static_cast<int>(fx);
    y = static_cast<int>(fy);
    double t0, t1;
    columnRange(x, y, t0, t1);
    if (local() && nearDepth[columnIndex(x, y)] > farDepth[columnIndex(x, y)]) return false;
    const double t = depthToSliceCoord(ndc.z * 0.5 + 0.5);
    double fs = (t - t0) / (t1 - t0) * slices;
    // A local column's range is closed and came through float: its near and far surfaces
    // (and rounding just past them) belong to the first and last slice.
    const double slack = local() ? 1e-3 : 0.0;
    if (fs < -slack || fs >= slices + slack) return false;
    s = std::clamp(static_cast<int>(std::floor(fs)), 0, slices - 1);
    return true;
}

glm::dvec3 SliceMap::cellCenter(int x, int y, int s) const {
    double t0, t1;
    columnRange(x, y, t0, t1);
    const double t = t0 + (s + 0.5) / slices * (t1 - t0);
    const glm::dvec4 ndc((x + 0.5) / width * 2.0 - 1.0, (y + 0.5) / height * 2.0 - 1.0,
                         2.0 * sliceCoordToDepth(t) - 1.0, 1.0);
    const glm::dvec4 w = glm::inverse(viewProj) * ndc;
    return glm::dvec3(w) / w.w;
}

bool SliceMap::occupied(const glm::dvec3& world) const {
    int x, y, s;
    return locate(world, x, y, s) && get(x, y, s);
}

int SliceMap::countOccupied(int x, int y, int s0, int s1) const {
    s0 = std::max(s0, 0);
    s1 = std::min(s1, slices - 1);
    if (s1 < s0) return 0;
    const std::uint32_t* col = &words[columnIndex(x, y) * wordsPerColumn()];
    int n = 0;
    for (int w = s0 / 32; w <= s1 / 32; ++w) {
        std::uint32_t m = ~0u;
        if (w == s0 / 32) m &= ~0u << (s0 % 32);
        if (w == s1 / 32 && s1 % 32 != 31) m &= (1u << (s1 % 32 + 1)) - 1u;
        n += std::popcount(col[w] & m);
    }
    return n;
}

int SliceMap::firstOccupied(int x, int y) const {
    const std::uint32_t* col = &words[columnIndex(x, y) * wordsPerColumn()];
    for (int w = 0; w < wordsPerColumn(); ++w)
        if (col[w]) return w * 32 + std::countr_zero(col[w]);
    return -1;
}

int SliceMap::lastOccupied(int x, int y) const {
    const std::uint32_t* col = &words[columnIndex(x, y) * wordsPerColumn()];
    for (int w = wordsPerColumn() - 1; w >= 0; --w)
        if (col[w]) return w * 32 + 31 - std::countl_zero(col[w]);
    return -1;
}

double SliceMap::thickness(int x, int y) const {
    // Slices are equal steps of the slice coordinate, which is linear along the column's
    // centre ray for both ortho (window depth) and perspective (eye depth) grids.
    const glm::dvec3 a = cellCenter(x, y, 0), b = cellCenter(x, y, std::min(1, slices - 1));
    const double step = slices > 1 ? glm::length(b - a) : 0.0;
    return step * countOccupied(x, y, 0, slices - 1);
}

SliceMap makeOrthoGrid(const glm::dvec3& lo, const glm::dvec3& hi, int width, int height,
                       int slices) {
    VEIL_CHECK(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z, "grid bounds are empty");
    SliceMap m;
    m.width = width;
    m.height = height;
    m.slices = slices;
    const glm::dvec3 e = hi - lo;
    // Columns along +z: NDC = 2 (p - lo) / e - 1 on every axis (window depth grows with z).
    glm::dmat4 p(1.0);
    for (int i = 0; i < 3; ++i) {
        p[i][i] = 2.0 / e[i];
        p[3][i] = -2.0 * lo[i] / e[i] - 1.0;
    }
    m.viewProj = p;
    m.allocate();
    return m;
}

SliceMap makeFittedCubeGrid(const glm::dvec3& lo, const glm::dvec3& hi, int res) {
    VEIL_CHECK(res > 0, "grid resolution {} must be positive", res);
    const glm::dvec3 e = hi - lo;
    const double extent = std::max({e.x, e.y, e.z, 1e-9}) * 1.06;
    const glm::dvec3 c = 0.5 * (lo + hi);
    return makeOrthoGrid(c - 0.5 * extent, c + 0.5 * extent, res, res, res);
}

void gridBounds(const SliceMap& map, glm::dvec3& lo, glm::dvec3& hi) {
    const glm::dmat4 inv = glm::inverse(map.viewProj);
    lo = glm::dvec3(1e300);
    hi = glm::dvec3(-1e300);
    for (int i = 0; i < 8; ++i) {
        glm::dvec4 p = inv * glm::dvec4(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1, 1.0);
        const glm::dvec3 q = glm::dvec3(p) / p.w;
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
}

SliceMap axisView(const SliceMap& grid, int axis) {
    VEIL_CHECK(!grid.perspective && axis >= 0 && axis < 3,
               "axis views need an orthographic grid and axis 0..2");
    glm::dvec3 lo, hi;
    gridBounds(grid, lo, hi);
    const int n[3] = {grid.width, grid.height, grid.slices};
    // (column u, column v, depth) = world axes (a+1, a+2, a) cyclically.
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    SliceMap m;
    m.width = n[u];
    m.height = n[v];
    m.slices = n[axis];
    const glm::dvec3 e = hi - lo;
    glm::dmat4 p(0.0);
    const int rows[3] = {u, v, axis};
    for (int r = 0; r < 3; ++r) {
        p[rows[r]][r] = 2.0 / e[rows[r]];
        p[3][r] = -2.0 * lo[rows[r]] / e[rows[r]] - 1.0;
    }
    p[3][3] = 1.0;
    m.viewProj = p;
    m.allocate();
    return m;
}

SliceMap makePerspectiveGrid(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                             double fovYDegrees, double nearPlane, double farPlane, int width,
                             int height, int slices) {
    VEIL_CHECK(nearPlane > 0.0 && farPlane > nearPlane, "perspective grid needs 0 < near < far");
    SliceMap m;
    m.width = width;
    m.height = height;
    m.slices = slices;
    m.perspective = true;
    m.nearPlane = nearPlane;
    m.farPlane = farPlane;
    m.viewProj =
        glm::perspective(glm::radians(fovYDegrees), double(width) / height, nearPlane, farPlane) *
        glm::lookAt(eye, target, up);
    m.allocate();
    return m;
}

} // namespace veil::voxelize
