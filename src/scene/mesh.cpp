// Procedural shapes and mesh bounds. Every shape is centred at the origin with y up, CCW
// front faces and outward unit normals; the unit tests check winding, closure and area.
#include "scene/mesh.h"

#include "base/error.h"

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <limits>

namespace veil::scene {

namespace {

constexpr float kPi = glm::pi<float>();

// PCG32 ([ONeill14], pcg32_random_r): our own generator because std:: distributions
// produce different sequences across standard libraries, and particle clouds must be
// identical everywhere for a given seed.
class Pcg32 {
public:
    explicit Pcg32(std::uint64_t seed, std::uint64_t stream = 0x5851f42d4c957f2dULL)
        : inc_((stream << 1u) | 1u) {
        next();
        state_ += seed;
        next();
    }
    std::uint32_t next() {
        std::uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [0,1) with 24 bits, exact in float.
    float uniform() { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }

private:
    std::uint64_t state_ = 0;
    std::uint64_t inc_;
};

void addQuadIndices(MeshData& m, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                    std::uint32_t d) {
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

} // namespace

void MeshData::bounds(glm::vec3& lo, glm::vec3& hi) const {
    if (positions.empty()) {
        lo = hi = glm::vec3(0.0f);
        return;
    }
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = glm::vec3(std::numeric_limits<float>::lowest());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        float pad = (billboard && i < billboardSize.size()) ? billboardSize[i] : 0.0f;
        lo = glm::min(lo, positions[i] - glm::vec3(pad));
        hi = glm::max(hi, positions[i] + glm::vec3(pad));
    }
}

MeshData makePlane(glm::vec2 size, int subdivisions) {
    VEIL_CHECK(size.x > 0.0f && size.y > 0.0f, "plane size must be positive, got [{}, {}]", size.x,
               size.y);
    VEIL_CHECK(subdivisions >= 1, "plane subdivisions must be >= 1, got {}", subdivisions);
    MeshData m;
    m.name = "plane";
    const int n = subdivisions;
    for (int iz = 0; iz <= n; ++iz) {
        for (int ix = 0; ix <= n; ++ix) {
            float u = float(ix) / float(n), v = float(iz) / float(n);
            m.positions.emplace_back((u - 0.5f) * size.x, 0.0f, (v - 0.5f) * size.y);
            m.normals.emplace_back(0.0f, 1.0f, 0.0f);
            m.uvs.emplace_back(u, v);
        }
    }
    auto at = [n](int ix, int iz) { return std::uint32_t(iz * (n + 1) + ix); };
    for (int iz = 0; iz < n; ++iz) {
        for (int ix = 0; ix < n; ++ix) {
            // Seen from +y (x right, z toward the viewer) this order is counter-clockwise.
            addQuadIndices(m, at(ix, iz), at(ix, iz + 1), at(ix + 1, iz + 1), at(ix + 1, iz));
        }
    }
    return m;
}

MeshData makeBox(glm::vec3 size) {
    VEIL_CHECK(size.x > 0.0f && size.y > 0.0f && size.z > 0.0f,
               "box size must be positive, got [{}, {}, {}]", size.x, size.y, size.z);
    MeshData m;
    m.name = "box";
    const glm::vec3 h = size * 0.5f;
    // Each face: normal n and in-plane axes u, v with cross(u, v) = n, so the corner order
    // -u-v, +u-v, +u+v, -u+v is counter-clockwise seen from outside.
    const glm::vec3 axes[6][3] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const auto& face : axes) {
        const glm::vec3 n = face[0], u = face[1], v = face[2];
        auto base = std::uint32_t(m.positions.size());
        for (const glm::vec2& c : corners) {
            m.positions.push_back((n + c.x * u + c.y * v) * h);
            m.normals.push_back(n);
            m.uvs.emplace_back(0.5f * (c.x + 1.0f), 0.5f * (c.y + 1.0f));
        }
        addQuadIndices(m, base, base + 1, base + 2, base + 3);
    }
    return m;
}

MeshData makeSphere(float radius, int segments, int rings) {
    VEIL_CHECK(radius > 0.0f, "sphere radius must be positive, got {}", radius);
    VEIL_CHECK(segments >= 3 && rings >= 2, "sphere needs segments >= 3 and rings >= 2, got {}, {}",
               segments, rings);
    MeshData m;
    m.name = "sphere";
    // Ring i at polar angle theta = pi i / rings from +y; segment j at azimuth phi, turning
    // from +x toward -z (counter-clockwise seen from +y). The seam column is duplicated for UVs.
    for (int i = 0; i <= rings; ++i) {
        float theta = kPi * float(i) / float(rings);
        for (int j = 0; j <= segments; ++j) {
            float phi = 2.0f * kPi * float(j) / float(segments);
            glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                        -std::sin(theta) * std::sin(phi));
            if (i == 0 || i == rings) n = glm::vec3(0.0f, i == 0 ? 1.0f : -1.0f, 0.0f);
            m.positions.push_back(radius * n);
            m.normals.push_back(n);
            m.uvs.emplace_back(float(j) / float(segments), 1.0f - float(i) / float(rings));
        }
    }
    auto at = [segments](int i, int j) { return std::uint32_t(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < segments; ++j) {
            std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            // The pole rings would give zero-area triangles; leave them out.
            if (i != rings - 1) m.indices.insert(m.indices.end(), {a, b, c});
            if (i != 0) m.indices.insert(m.indices.end(), {a, c, d});
        }
    }
    return m;
}

MeshData makeTorus(float majorRadius, float minorRadius, int majorSegments, int minorSegments) {
    VEIL_CHECK(majorRadius > 0.0f && minorRadius > 0.0f && minorRadius < majorRadius,
               "torus needs 0 < minor_radius < major_radius, got major {} minor {}", majorRadius,
               minorRadius);
    VEIL_CHECK(majorSegments >= 3 && minorSegments >= 3,
               "torus needs at least 3 segments each way, got {}, {}", majorSegments,
               minorSegments);
    MeshData m;
    m.name = "torus";
    // Around the y axis in the xz plane; u turns like the sphere's azimuth, v around the tube
    // starting at the outer equator and going up.
    for (int i = 0; i <= majorSegments; ++i) {
        float u = 2.0f * kPi * float(i) / float(majorSegments);
        glm::vec3 radial(std::cos(u), 0.0f, -std::sin(u));
        for (int j = 0; j <= minorSegments; ++j) {
            float v = 2.0f * kPi * float(j) / float(minorSegments);
            glm::vec3 n = std::cos(v) * radial + glm::vec3(0.0f, std::sin(v), 0.0f);
            m.positions.push_back(majorRadius * radial + minorRadius * n);
            m.normals.push_back(n);
            m.uvs.emplace_back(float(i) / float(majorSegments), float(j) / float(minorSegments));
        }
    }
    auto at = [minorSegments](int i, int j) { return std::uint32_t(i * (minorSegments + 1) + j); };
    for (int i = 0; i < majorSegments; ++i) {
        for (int j = 0; j < minorSegments; ++j) {
            addQuadIndices(m, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return m;
}

MeshData makeParticleCloud(int count, float radius, float particleSize, std::uint32_t seed) {
    VEIL_CHECK(count >= 1, "particle count must be >= 1, got {}", count);
    VEIL_CHECK(count <= (1 << 26), "particle count {} is too large (max {})", count, 1 << 26);
    VEIL_CHECK(radius > 0.0f && particleSize > 0.0f,
               "particle radius and particle_size must be positive, got {}, {}", radius,
               particleSize);
    MeshData m;
    m.name = "particles";
    m.billboard = true;
    const auto n = std::size_t(count);
    m.positions.reserve(4 * n);
    m.normals.reserve(4 * n);
    m.uvs.reserve(4 * n);
    m.billboardSize.reserve(4 * n);
    m.indices.reserve(6 * n);
    Pcg32 rng(seed);
    // Each coordinate is the mean of four uniforms (Irwin-Hall, a bell of std-dev 1/sqrt(12)
    // of the ball's diameter); points outside the unit ball are drawn again. Only + and * are
    // used, so the cloud is bit-identical on every platform.
    auto coord = [&rng] {
        float s = rng.uniform() + rng.uniform() + rng.uniform() + rng.uniform();
        return 0.5f * s - 1.0f;
    };
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (std::size_t p = 0; p < n; ++p) {
        glm::vec3 c;
        do {
            c = glm::vec3(coord(), coord(), coord());
        } while (glm::dot(c, c) > 1.0f);
        c *= radius;
        auto base = std::uint32_t(m.positions.size());
        for (const glm::vec2& corner : corners) {
            m.positions.push_back(c);
            m.normals.emplace_back(0.0f, 0.0f, 1.0f);
            m.uvs.push_back(corner);
            m.billboardSize.push_back(particleSize);
        }
        addQuadIndices(m, base, base + 1, base + 2, base + 3);
    }
    return m;
}

} // namespace veil::scene
