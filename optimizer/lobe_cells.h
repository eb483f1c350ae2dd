// The fit's fast objective measures an output texel's impulse-response L1 over cells instead of
// every base texel: base texels near the output direction R, where the lobe is sharp and the taps
// read fine pyramid levels, and ever larger squares of them (texels of coarser pyramid levels)
// further away, where the lobe and the response are smooth. The response's mass in a cell is the
// weight its taps put there, pushed down the pyramid only as far as the cell's level; so the cost
// of a texel grows with the number of cells (about the logarithm of the face size), not with the
// face size. `probefit eval` (every base texel) stays the judge; the test
// `LobeCells.FastObjectiveIsCloseToTheExactL1` bounds the difference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "probe/lobe.h"

namespace probefit {

// A cell is one texel of pyramid level `level` (face size faceSize >> level): the base texels it
// covers. kernel: the reference's normalized mass there; tail: whether it lies beyond the tail
// radius (tail_check.h).
struct LobeCell {
    std::uint32_t index = 0;
    std::uint8_t level = 0;
    bool tail = false;
    float kernel = 0.0f;
};

// A cell is measured whole where its nearest point lies at least this many of its angular radii
// from R (closer, it splits into its four children; base texels always stand alone).
inline constexpr double kCellDistance = 3.0;
// ... and where the lobe varies across it (max - min of the density at its centre and corners) by
// less than this share of its largest value there, or by less than kCellVariation of the lobe's
// whole mass times the cell's solid angle: so a lobe that is sharp away from R (a ring) is resolved
// there too.
inline constexpr double kCellRelativeVariation = 0.5;
inline constexpr double kCellVariation = 1e-4;

// The reference's density K(R, l) (unnormalized) of a lobe about the output direction R.
using LobeDensity = std::function<double(const glm::dvec3& l)>;

// The cells as the quadtree that split them, one node per pyramid texel visited: nodes 0-5 are the
// faces' top texels; a node >= 0 is the cell it holds, a node < 0 was split and ~node is the first of
// its four children (i, j order: (2i, 2j), (2i + 1, 2j), (2i, 2j + 1), (2i + 1, 2j + 1)). A few
// thousand nodes per texel: looking a texel's cell up in them stays in the core's own cache,
// where a per-level map of the whole cube would not.
struct CellTree {
    std::vector<std::int32_t> nodes;
    int top = 0; // the faces' top pyramid level

    // The cell that holds texel (face, i, j) of pyramid level `level`: the texel itself or its
    // nearest ancestor that is a cell; -1 where the cells there are finer than the texel.
    std::int32_t cellAt(int level, int face, int i, int j) const {
        std::int32_t node = nodes[static_cast<std::size_t>(face)];
        for (int a = top - 1; a >= level && node < 0; --a) {
            const int shift = a - level;
            node = nodes[static_cast<std::size_t>(~node + ((i >> shift) & 1) + 2 * ((j >> shift) & 1))];
        }
        return node >= 0 ? node : -1;
    }
};

// Asks the core to load `bytes` from `data` into its cache, a line at a time.
inline void prefetchBytes(const void* data, std::size_t bytes) {
    for (std::size_t offset = 0; offset < bytes; offset += 64) __builtin_prefetch(static_cast<const char*>(data) + offset);
}

// What the cells' pass has learnt of the pyramid texels one output texel's taps reach: for each,
// the cells its response spreads over, or the texels of the level below that it is pushed down to.
// That depends on the cells alone, not on the taps, so it is kept from one evaluation to the next
// (the taps move little between them) and grows as they reach new texels; and it is small, so the
// pass runs in the core's own cache whatever the face size.
struct CellRoutes {
    struct Node {
        std::uint32_t key = 0;   // key(level, index)
        std::uint32_t begin = 0; // its first cell (spread) or child (pushed down)
        std::uint8_t count = 0;
        bool pushed = false;
    };
    // A pushed-down texel's node of its operator row and its weight there (a float, as the kernel the
    // pass measures against: the pass is bound by memory).
    struct Child {
        std::int32_t node = 0;
        float weight = 0.0f;
    };
    std::vector<Node> nodes;
    std::vector<std::int32_t> cells; // a spread's cells: one at the base, nine above (the level's stencil)
    std::vector<Child> children;

    static std::uint32_t key(int level, std::uint32_t index) { return static_cast<std::uint32_t>(level) << 28 | index; }
    // The node of `key`, or -1.
    std::int32_t find(std::uint32_t key) const;
    // A new node for `key` (not yet present): its id.
    std::int32_t add(std::uint32_t key);
    // Asks the core to load the routes into its cache (the cells' pass walks them in an order the
    // hardware prefetcher cannot follow).
    void prefetch() const;

private:
    std::vector<std::int32_t> slots_; // open addressing on the key: node id + 1, 0 where free
};

struct LobeCells {
    std::vector<LobeCell> cells; // a partition of the base texels
    CellTree tree;
    double kernelTail = 0.0; // the reference's mass in the tail cells
};

// The cells of output direction R (unit) over a base of `faceSize`; tailRadius in radians (<= 0: no
// tail). The kernel of a cell is the density summed over its base texels (cells of up to 4x4 base
// texels) or over its 4x4 sub-texels (larger cells, where the lobe is smooth), times their exact
// solid angles, normalized to sum 1 over all cells.
LobeCells lobeCells(const glm::dvec3& R, int faceSize, const LobeDensity& density, double tailRadius);

// The reference lobe of probe/reference.h (GGX or Charlie) at the level's alpha.
LobeDensity lobeDensity(const glm::dvec3& R, const probe::LevelLobe& lobe);

} // namespace probefit
