// The impulse-response L1 of one output texel under a table's taps, with its gradient: exactly the
// runtime's model from probecore (frames, taps, trilinear footprints, the transposed pyramid),
// against the reference lobe. The gradient uses the adjoint: d e / d(weight on pyramid texel p) is
// the pyramid (pulled up through the same operators) of sign(w - k) over base texels.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "dense_passes.h"
#include "lobe_cells.h"
#include "probe/frame.h"
#include "probe/pyramid.h"
#include "probe/reference.h"
#include "probe/stratified_texels.h"
#include "probe/tap_table.h"

namespace probefit {

// An output texel with everything that does not depend on the coefficients.
struct OutputTexel {
    probe::Texel texel;
    double weight = 0.0; // weight of its error in the level's mean
    glm::dvec3 cubeVector{0.0};
    std::array<probe::FrameSetup, probe::kFrameCount> frames;
    // The reference k(R, t) over base texels, sum 1: all of it in `kernel` (the fit's texels, whose
    // terms and slope read every texel), or texel by texel from `lobe` (measured texels: the error
    // alone, read only where the taps reach; kernelSum is then 1).
    std::vector<float> kernel;
    double kernelSum = 0.0; // sum of the kernel (1 up to float rounding)
    std::optional<probe::ReferenceLobe> lobe;
    // Or over cells (lobe_cells.h): the fit's fast objective, whose cost does not grow with the base.
    std::vector<LobeCell> cells;
    CellTree cellTree;
    // Kept between evaluations of this texel, which one thread at a time makes (a memo: it changes
    // no result).
    mutable CellRoutes routes;
    double kernelAt(std::uint32_t t) const { return lobe ? (*lobe)(t) : static_cast<double>(kernel[t]); }
    // The lobe's tail (tail_check.h), for the tail term only (empty without it): bit t set where
    // base texel t lies beyond the tail radius of the level from R, and the reference's mass there.
    std::vector<std::uint64_t> tail;
    double kernelTail = 0.0;
};

// Asks the core to load a fitted texel's cells and routes into its cache: the cells' pass is bound by
// memory, so the objective fetches the next texel's while it measures one (about a fifth of its time).
inline void prefetch(const OutputTexel& texel) {
    texel.routes.prefetch();
    prefetchBytes(texel.cells.data(), texel.cells.size() * sizeof(LobeCell));
}

// How a fitted texel's reference is held: over every base texel (exact), or over cells (lobe_cells.h).
enum class Measure { exact, cells };

// One texel of output level m filtered with `lobe` (not a copy), its kernel (and with `tail` its
// tail) included; `geometry` is that of the base.
OutputTexel makeOutputTexel(const probe::WeightedTexel& texel, const probe::CubeGeometry& geometry, int level, const probe::LevelLobe& lobe,
                            bool tail = false);

// The same texel with its reference over cells.
OutputTexel makeCellTexel(const probe::WeightedTexel& texel, int faceSize, int level, const probe::LevelLobe& lobe, bool tail = false);

// The same texel with the kernel as a lobe of known normalization (probe::ReferenceLobe), for measuring.
OutputTexel makeMeasuredTexel(const probe::WeightedTexel& texel, const probe::CubeGeometry& geometry, int level,
                              const probe::LevelLobe& lobe, double normalization);

// All of them at once, all cores (for the fit, which revisits them every iteration).
std::vector<OutputTexel> prepareTexels(const std::vector<probe::WeightedTexel>& texels, int faceSize, int level,
                                       const probe::LevelLobe& lobe, bool tail = false, Measure measure = Measure::exact);

// Functions of the base texels whose moments the fit's terms compare, pulled up the pyramid: since a
// moment is linear in the response, the moment of a weight on pyramid texel p is that weight times
// the pulled-up basis at p, and no response needs building.
//   sh: the order-1 and order-2 real SH (probe/sh.h without the constant, which every normalized
//       response reproduces): the smooth content of the seam term (seam_term.h).
//   checkers: +-1 checkerboards of squares S/4, S/8, S/16 and S/32 texels (at least 1), each aligned
//       with the face and shifted by half a square, the colour flipped from face to face: the sharp,
//       high-frequency content of the checker term (checker_term.h).
inline constexpr int kMomentCount = 8;
enum class MomentFunctions { sh, checkers };
class MomentBasis {
public:
    MomentBasis(int faceSize, probe::PyramidSettings pyramid, MomentFunctions functions = MomentFunctions::sh);
    MomentBasis() = default; // none: for a fit without the term that reads it
    const double* at(std::uint32_t texel) const { return at(0, texel); }
    const double* at(int level, std::uint32_t texel) const {
        return &levels_[static_cast<std::size_t>(level)][static_cast<std::size_t>(texel) * kMomentCount];
    }

private:
    std::vector<std::vector<double>> levels_; // per pyramid level, kMomentCount values per texel
};

// Where the response of a weight on one pyramid texel falls, as masses on the base texels under
// it and its eight neighbours (row-major, the texel in the middle): its B-spline reaches past its
// own square. Per level, measured at face 0's centre (the pyramid's weighting by solid angle makes it
// vary a little over a face); level 0 and levels too small for it keep the texel's own square.
std::vector<std::array<double, 9>> responseSpread(int faceSize, const std::vector<probe::DownsampleOperator>& operators);

class ImpulseModel {
public:
    // With tailWeight T > 0, the gradients evaluate() gives are those of e + T |W - K| (the tail term:
    // the response's mass in the lobe's tail against the reference's), which keeps a fit from trading
    // the far tail away for the lobe's centre; the error it reports stays the L1.
    ImpulseModel(int faceSize, probe::PyramidSettings pyramid, int taps, probe::TableForm form, double tailWeight = 0.0);

    int taps() const { return taps_; }
    int blockSize() const { return probe::kTapParameterCount * probe::coefficientCount(form_); }
    int blockCount() const { return probe::kFrameCount * taps_; }
    double tailWeight() const { return tailWeight_; }

    // Per-thread scratch. Only the texels that the taps reach (their footprints pushed back
    // through the transposed pyramid) are visited: `touched` lists them per level, `stamp` marks
    // them; weights and adjoint are zero elsewhere between calls.
    struct Workspace {
        std::vector<std::vector<double>> weights, adjoint; // per pyramid level
        std::vector<std::vector<std::uint32_t>> touched, stamp;
        std::uint32_t generation = 0;
        // The cells' pass, over the nodes of the texel's CellRoutes: the footprints' weights and
        // nodes in tap order, and per node its weight, slope and stamp; the nodes touched per level.
        struct FootprintWeight {
            int level;
            std::uint32_t index;
            double weight;
        };
        std::vector<FootprintWeight> footprint;
        std::vector<std::int32_t> footprintNodes;
        std::vector<double> footprintAdjoint; // d e / d w at each footprint texel, in tap order
        std::vector<double> nodeWeight, nodeAdjoint;
        std::vector<std::uint32_t> nodeStamp;
        std::vector<std::vector<std::int32_t>> nodeTouched;
        std::vector<double> cellMass, cellSlope;
    };
    Workspace workspace() const;

    struct Result {
        double error = 0.0;     // e(R) in [0, 2]
        double tail = 0.0;      // |W - K|: the response's mass in the tail against the reference's
        double weightSum = 0.0; // sum of tap weights (frame weights included), before normalization
    };

    // e(R) with coefficients in blocks[frame * taps + tap] (kTapParameterCount * coefficientCount
    // values each). With `gradient` (blockCount * blockSize values, overwritten) also d e / d coefficient
    // and, with `weightSumGradient` (same size), d weightSum / d coefficient. A measured texel (one
    // with a lobe) has no gradient: std::logic_error.
    Result evaluate(const double* const* blocks, const OutputTexel& texel, Workspace& ws, double* gradient = nullptr,
                    double* weightSumGradient = nullptr) const;

    // Smooth moments of the response instead of its L1: m_j = sum_t w(R, t) Y_j(t) over the base texels
    // for the kMomentCount basis functions of `basis`, into `moments` (may be null). With `gradient`,
    // also d(sum_j c_j m_j) / d coefficient for the given c (kMomentCount values).
    void moments(const double* const* blocks, const OutputTexel& texel, const MomentBasis& basis, double* moments,
                 const double* c = nullptr, double* gradient = nullptr) const;

private:
    template <int K>
    Result evaluateWith(const double* const* blocks, const OutputTexel& texel, Workspace& ws, double* gradient,
                        double* weightSumGradient) const;
    // The L1 of the weights in ws.footprint (the taps reach up to pyramid level `top`) over the base
    // texels or the texel's cells, its tail mass error into *tail and, with `adjoint`, the slope at
    // each footprint texel into ws.footprintAdjoint.
    double measureBase(const OutputTexel& texel, Workspace& ws, int top, bool adjoint, double* tail) const;
    double measureCells(const OutputTexel& texel, Workspace& ws, bool adjoint, double* tail) const;
    // The node of pyramid texel (level k, index p) in the texel's routes, made (with the nodes it is
    // pushed down to) where it is new.
    std::int32_t routeOf(const OutputTexel& texel, int k, std::uint32_t p) const;
    template <int K>
    void momentsWith(const double* const* blocks, const OutputTexel& texel, const MomentBasis& basis, double* moments, const double* c,
                     double* gradient) const;

    int faceSize_;
    int pyramidLevels_;
    int taps_;
    probe::TableForm form_;
    double tailWeight_;
    std::vector<probe::DownsampleOperator> operators_;
    DensePasses dense_;
    std::vector<std::array<double, 9>> spread_; // responseSpread
};

// The reference's moments: sum_t k(R, t) Y_j(t) over the texel's kernel.
std::array<double, kMomentCount> kernelMoments(const OutputTexel& texel, const MomentBasis& basis);

// Block pointers into one level's coefficients of a table.
std::vector<const double*> levelBlocks(const probe::TapTable& table, int level);

} // namespace probefit
