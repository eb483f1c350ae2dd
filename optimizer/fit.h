// The fit: per output level, Ceres minimizes the impulse-response L1 of the table over the
// stratified texels (BFGS on the L1 itself, or Levenberg-Marquardt with one residual per texel).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "impulse_model.h"
#include "probe/tap_table.h"

namespace probefit {

// bfgs: BFGS only; lm: Levenberg-Marquardt only; lm-bfgs: lmIterations of Levenberg-Marquardt, then BFGS.
enum class FitSolver { lmBfgs, bfgs, lm };

// What a fit measures exactly after each level (the judge, evaluate.h) and records in the table.
enum class Records {
    none,       // nothing exact (probefit eval measures the table afterwards); the lowest weight sum alone
    stratified, // the stratified texels
    all,        // the stratified texels and every output texel
};

struct FitSettings {
    int faceSize = 0;
    int levelCount = 0;
    int taps = 0;
    probe::TableForm form = probe::TableForm::quadratic;
    probe::RoughnessMapping mapping = probe::RoughnessMapping::gltf;
    probe::Lobe lobe = probe::Lobe::ggx;
    probe::PyramidSettings pyramid;
    int stratifiedBudget = 512; // texels per level
    // The fit's L1: over cells (lobe_cells.h: its cost does not grow with the face size) or over
    // every base texel. The table's records are exact either way.
    Measure measure = Measure::cells;
    FitSolver solver = FitSolver::lmBfgs;
    int lmIterations = 10; // the Levenberg-Marquardt part of lm-bfgs (scaled like maxIterations)
    // Solver iterations for a level with the full budget of stratified texels; a level with fewer
    // texels (the rough ones: 24 at a 2x2 face) costs less per iteration and gets proportionally
    // more, at most roughIterationFactor times as many.
    int maxIterations = 30;
    // BFGS iterations with the frames tied on the coarse texels (every few of the stratified texels,
    // at least 128; a level with fewer than 256 has none) before maxIterations on all of them with
    // each frame free: the L1 falls slowly under BFGS, and a quarter of the texels points the same
    // way. 0: neither the tied part nor the coarse texels.
    int coarseIterations = 150;
    int roughIterationFactor = 4;
    // The seam term (seam_term.h): its weight W against the mean L1 (0: off), over at most this many
    // edge pairs per level.
    double seamWeight = 0.0;
    int seamPairBudget = 128;
    // The tail term's weight T (impulse_model.h): each texel's e + T |W - K| (0: off).
    double tailWeight = 0.0;
    // The checker term's weight C (checker_term.h): each texel's e + C c (0: off).
    double checkerWeight = 0.0;
    // Fits per level: from the best start candidate and, where > 1, also from starts - 1 importance
    // layouts (initial_layout.h) turned apart about the axis; the lowest objective is kept.
    int starts = 1;
    // With several starts and lm-bfgs, only the start with the lowest objective after
    // Levenberg-Marquardt goes on to BFGS; screenAll runs every start in full.
    bool screenAll = false;
    // Hops per level after the fit (initial_layout.h's hopLayout): each refits from the best fit so
    // far, moved at random, and is kept where its objective is lower.
    int hops = 0;
    Records records = Records::all;
    std::vector<probe::TapTable> inits; // --init tables: same size and levels, N or N/2 taps, either form
    // The bank (--bank): tables of any size, level count or mapping with the same taps and pyramid;
    // each offers its level of the nearest roughness as a start (initial_layout.h's startFromBank).
    struct BankTable {
        std::string name;
        probe::TapTable table;
    };
    std::vector<BankTable> bank;
    // The bank's levels (the best on a few texels) that start a fit: each is screened like the
    // other starts, since a start's L1 does not tell which basin is deepest.
    int bankStarts = 3;
    // Levels to fit (empty: all); the others are copied from the first init, which then must have the
    // table's taps and form, so one level can be refitted without paying for the rest.
    std::vector<int> fitLevels;
    // The fitted levels start from the lobe layout and the previous level alone, and keep no init's
    // filter: the inits only supply the levels not fitted. A refit that trades L1 for a stronger seam
    // or tail term needs it, since the init's filter, with its lower L1, would otherwise be kept.
    bool fresh = false;
    // A table written by an interrupted fit of the same shape and solver (--resume): its measured
    // levels are taken as they are, the others fitted.
    const probe::TapTable* resume = nullptr;
};

struct FitProgress {
    int level = 0;
    int iteration = 0;
    double l1 = 0.0; // stratified mean impulse L1 (plus the weight-sum penalty where it is active)
    double seconds = 0.0;
    std::string stage; // "start <candidate>", "iteration", "done", "all texels", "seam term" (l1: the mean s)
    // With "done": where the level's time went (levels fitted at once each count their own).
    double levelSeconds = 0.0;      // the level's whole time, its kernels included
    double kernelSeconds = 0.0;     // reference kernels of the stratified texels
    double evaluationSeconds = 0.0; // the model: L1 and its gradient (or Jacobian) inside the solver
    double solverSeconds = 0.0;     // the rest of the solver (BFGS updates, line search, or LM linear algebra)
    int evaluations = 0;            // model evaluations over all stratified texels
};

// Whether level m is copied from the first --init with its records (it is not fitted, and the init
// measured it on the same stratified texels, or the fit records nothing exact): such a level costs nothing.
bool copiesInitRecords(const FitSettings& settings, int m);

// Whether a level of a fit's table (or of its checkpoint) is finished: it records its lowest weight
// sum, which every fit measures, with or without its exact L1.
bool levelFinished(const probe::TableLevel& level);

// Whether only the start with the lowest objective after Levenberg-Marquardt goes on to BFGS.
bool screensStarts(const FitSettings& settings);

// The iteration limit of a level with `texels` stratified texels, for `iterations` at the full budget.
int levelIterations(const FitSettings& settings, int iterations, std::size_t texels);

// The coarse texels of a level with this many stratified texels: every few of them, at least 128.
std::size_t coarseTexelCount(std::size_t texels);

// A level's solver iterations over every start, screening and hop, in iterations over all its
// stratified texels (a coarse iteration counts as its share of them): what the estimate scales.
double levelIterationCost(const FitSettings& settings, std::size_t texels);

FitSolver parseFitSolver(const std::string& name);

// Fits every level with alpha > 0; deterministic for given settings. Throws ProbeError for bad settings.
// `levelDone` sees the table after each level is finished (for a checkpoint that --resume reads).
probe::TapTable fitTable(const FitSettings& settings, const std::function<void(const FitProgress&)>& progress,
                         const std::function<void(const probe::TapTable&)>& levelDone = {});

} // namespace probefit
