#include "lobe_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>

#include <glm/geometric.hpp>

#include "probe/cube.h"
#include "probe/pyramid.h"
#include "probe/roughness.h"

namespace probefit {

using namespace probe;

namespace {

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

// texelSolidAngle(x, y, size) of every texel of a face of `size`, made once per size and kept: it is
// the same on every face and for every output texel, and its four atan2 per texel would be most of
// the cells' cost.
const std::vector<double>& faceSolidAngles(int size) {
    static std::array<std::once_flag, 32> made;
    static std::array<std::vector<double>, 32> tables;
    const std::size_t k = static_cast<std::size_t>(log2Exact(size));
    std::call_once(made[k], [&] {
        tables[k].resize(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) tables[k][static_cast<std::size_t>(y * size + x)] = texelSolidAngle(x, y, size);
    });
    return tables[k];
}

class CellBuilder {
public:
    CellBuilder(const glm::dvec3& R, int faceSize, const LobeDensity& density, double tailRadius)
        : R_(R), faceSize_(faceSize), density_(density), tailRadius_(tailRadius) {}

    // The cells under texel (face, i, j) of pyramid level `level`, whose tree node is `node`; `mass` > 0
    // turns the variation test on.
    void split(int level, int face, int i, int j, double mass, std::size_t node, LobeCells& out) const {
        const int size = faceSize_ >> level;
        const glm::dvec3 centre = texelDirection({face, i, j}, size);
        const double theta = angleBetween(R_, centre);
        double radius = 0.0, lowest = density_(centre), highest = lowest;
        for (int c = 0; c < 4; ++c) {
            const double u = 2.0 * (i + (c & 1)) / size - 1.0, v = 2.0 * (j + (c >> 1)) / size - 1.0;
            const glm::dvec3 corner = glm::normalize(faceUvToCubePoint(face, u, v));
            radius = std::max(radius, angleBetween(centre, corner));
            if (mass > 0.0) {
                const double k = density_(corner);
                lowest = std::min(lowest, k);
                highest = std::max(highest, k);
            }
        }
        const bool far = theta - radius >= kCellDistance * radius;
        const bool straddlesTail = tailRadius_ > 0.0 && std::abs(theta - tailRadius_) < radius;
        const double variation = highest - lowest;
        const bool smooth = mass <= 0.0 || variation <= kCellRelativeVariation * highest ||
                            variation * texelSolidAngle(i, j, size) <= kCellVariation * mass;
        if (level == 0 || (far && !straddlesTail && smooth)) {
            out.tree.nodes[node] = static_cast<std::int32_t>(out.cells.size());
            out.cells.push_back({static_cast<std::uint32_t>(texelIndex({face, i, j}, size)), static_cast<std::uint8_t>(level),
                                 tailRadius_ > 0.0 && theta > tailRadius_, static_cast<float>(cellMass(level, face, i, j))});
            return;
        }
        const std::size_t children = out.tree.nodes.size();
        out.tree.nodes[node] = ~static_cast<std::int32_t>(children);
        out.tree.nodes.resize(children + 4);
        for (int c = 0; c < 4; ++c)
            split(level - 1, face, 2 * i + (c & 1), 2 * j + (c >> 1), mass, children + static_cast<std::size_t>(c), out);
    }

private:
    // The density times the exact solid angle, summed over the cell's base texels or, for larger
    // cells, over its 4x4 sub-texels.
    double cellMass(int level, int face, int i, int j) const {
        const int sub = std::max(0, level - 2), size = faceSize_ >> sub, span = 1 << (level - sub);
        const std::vector<double>& solidAngles = faceSolidAngles(size);
        double sum = 0.0;
        for (int y = j * span; y < (j + 1) * span; ++y)
            for (int x = i * span; x < (i + 1) * span; ++x)
                sum += density_(texelDirection({face, x, y}, size)) * solidAngles[static_cast<std::size_t>(y * size + x)];
        return sum;
    }

    glm::dvec3 R_;
    int faceSize_;
    const LobeDensity& density_;
    double tailRadius_;
};

} // namespace

LobeCells lobeCells(const glm::dvec3& R, int faceSize, const LobeDensity& density, double tailRadius) {
    const CellBuilder builder(R, faceSize, density, tailRadius);
    const int top = pyramidLevelCount(faceSize) - 1;
    // First by distance alone, for the lobe's whole mass; then again with the variation test.
    LobeCells result;
    for (int pass = 0; pass < 2; ++pass) {
        double mass = 0.0;
        for (const LobeCell& c : result.cells) mass += static_cast<double>(c.kernel);
        result.cells.clear();
        result.tree = {std::vector<std::int32_t>(kFaceCount), top};
        for (int face = 0; face < kFaceCount; ++face)
            builder.split(top, face, 0, 0, pass == 0 ? 0.0 : mass, static_cast<std::size_t>(face), result);
    }
    double total = 0.0;
    for (const LobeCell& c : result.cells) total += static_cast<double>(c.kernel);
    for (LobeCell& c : result.cells) {
        c.kernel = total > 0.0 ? static_cast<float>(static_cast<double>(c.kernel) / total) : 0.0f;
        if (c.tail) result.kernelTail += static_cast<double>(c.kernel);
    }
    return result;
}

namespace {
std::size_t slotOf(std::uint32_t key, std::size_t capacity) { return (key * 0x9E3779B1u) & (capacity - 1); }
} // namespace

std::int32_t CellRoutes::find(std::uint32_t key) const {
    if (slots_.empty()) return -1;
    for (std::size_t s = slotOf(key, slots_.size());; s = (s + 1) & (slots_.size() - 1)) {
        const std::int32_t id = slots_[s] - 1;
        if (id < 0 || nodes[static_cast<std::size_t>(id)].key == key) return id;
    }
}

std::int32_t CellRoutes::add(std::uint32_t key) {
    // At most half full, so a probe ends soon at a free slot.
    if (2 * (nodes.size() + 1) > slots_.size()) {
        slots_.assign(std::max<std::size_t>(1024, 2 * slots_.size()), 0);
        for (std::size_t id = 0; id < nodes.size(); ++id) {
            std::size_t s = slotOf(nodes[id].key, slots_.size());
            while (slots_[s] != 0) s = (s + 1) & (slots_.size() - 1);
            slots_[s] = static_cast<std::int32_t>(id) + 1;
        }
    }
    std::size_t s = slotOf(key, slots_.size());
    while (slots_[s] != 0) s = (s + 1) & (slots_.size() - 1);
    nodes.push_back({key, 0, 0, false});
    slots_[s] = static_cast<std::int32_t>(nodes.size());
    return static_cast<std::int32_t>(nodes.size()) - 1;
}

void CellRoutes::prefetch() const {
    prefetchBytes(nodes.data(), nodes.size() * sizeof(Node));
    prefetchBytes(cells.data(), cells.size() * sizeof(std::int32_t));
    prefetchBytes(children.data(), children.size() * sizeof(Child));
    prefetchBytes(slots_.data(), slots_.size() * sizeof(std::int32_t));
}

LobeDensity lobeDensity(const glm::dvec3& R, const LevelLobe& lobe) {
    return visitLobeKernel<double>(lobe.lobe, lobe.alpha, [&R](auto kernel) -> LobeDensity {
        return [R, kernel](const glm::dvec3& l) {
            const glm::dvec3 d = R - l;
            return kernel(glm::dot(R, l), glm::dot(d, d));
        };
    });
}

} // namespace probefit
