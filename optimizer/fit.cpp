#include "fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <optional>

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include "checker_term.h"
#include "evaluate.h"
#include "impulse_model.h"
#include "initial_layout.h"
#include "level_solver.h"
#include "probe/error.h"
#include "seam_term.h"
#include "tail_check.h"

namespace probefit {

using namespace probe;

namespace {

// How far apart (in texels of the tap's pyramid level) the two halves of a split --init tap start.
constexpr double kSplitSpread = 0.5;
// The bank's starts are screened on every this many stratified texels.
constexpr std::size_t kBankScreenStride = 8;
// The coarse texels: every few of the level's stratified texels, at least this many. Starts are
// screened on them, and the fit's first BFGS iterations run on them.
constexpr std::size_t kCoarseTexels = 128;

// The coarse texels are every this many of a level's stratified texels.
std::size_t coarseStride(std::size_t texels) { return std::max<std::size_t>(1, texels / kCoarseTexels); }

// The iterations of the solver's Levenberg-Marquardt and BFGS parts at the full texel budget.
int lmPart(const FitSettings& s) { return s.solver == FitSolver::lm ? s.maxIterations : s.lmIterations; }
int bfgsPart(const FitSettings& s) { return s.solver == FitSolver::lm ? 0 : s.maxIterations; }

// The level of `table` whose alpha is nearest alpha (by ratio, within a factor of 2); -1 if none.
int nearestLevel(const TapTable& table, double alpha) {
    int best = -1;
    double bestDistance = std::log(2.0);
    for (int m = 0; m < table.levelCount; ++m) {
        const double a = tableLevelAlpha(table, m);
        if (a <= 0.0) continue;
        const double distance = std::abs(std::log(a / alpha));
        if (distance <= bestDistance) {
            best = m;
            bestDistance = distance;
        }
    }
    return best;
}

double weightedMeanWeightSum(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels) {
    double sum = 0.0, total = 0.0;
    ImpulseModel::Workspace ws = model.workspace();
    for (const OutputTexel& t : texels) {
        sum += t.weight * model.evaluate(blocks, t, ws).weightSum;
        total += t.weight;
    }
    return sum / total;
}

void scaleWeights(TapTable& table, int level, double factor) {
    const int k = coefficientCount(table.form);
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t)
            for (int q = 0; q < k; ++q) table.levels[level].coefficients[table.offset(frame, t, tapWeight) + q] *= factor;
}

std::string initDescription(const FitSettings& s) {
    std::string text;
    if (s.fresh) return text;
    for (const TapTable& init : s.inits)
        text += fmt::format(", --init table {} {}x3{}", tableFormName(init.form), init.taps,
                            init.taps != s.taps ? fmt::format(" (taps split {} texels apart)", 2 * kSplitSpread) : "");
    if (!s.inits.empty()) text += "; an --init's exact filter is kept where the fit is not better";
    if (!s.bank.empty())
        text += s.bankStarts > 1 ? fmt::format(", the nearest roughness among {} bank tables (the {} best on every {}th texel "
                                               "are also starts)",
                                               s.bank.size(), s.bankStarts, kBankScreenStride)
                                 : fmt::format(", the nearest roughness among {} bank tables", s.bank.size());
    return text;
}

std::string solverDescription(const FitSettings& s) {
    const std::string lm = "Levenberg-Marquardt (dense normal Cholesky, residual sqrt(a e) per stratified output texel, function "
                           "tolerance 1e-6)";
    const std::string bfgs = "BFGS (Wolfe line search, function tolerance 1e-7)";
    std::string method;
    switch (s.solver) {
    case FitSolver::lmBfgs:
        method = s.coarseIterations > 0
                     ? fmt::format("{} iterations of {}, then at most {} of {} with every frame's taps tied (the best frame "
                                   "copied into the others) on the coarse texels (every few of the stratified output texels, at "
                                   "least {}) and at most {} on all of them with each frame free",
                                   s.lmIterations, lm, s.coarseIterations, bfgs, kCoarseTexels, s.maxIterations)
                     : fmt::format("{} iterations of {}, then at most {} of {}", s.lmIterations, lm, s.maxIterations, bfgs);
        break;
    case FitSolver::bfgs: method = fmt::format("at most {} iterations of {}", s.maxIterations, bfgs); break;
    case FitSolver::lm: method = fmt::format("at most {} iterations of {}", s.maxIterations, lm); break;
    }
    const std::string seam = s.seamWeight > 0.0
                                 ? fmt::format(" plus {} x the mean seam term over at most {} face-edge pairs (the change of "
                                               "the response's order-1 and order-2 SH moments across the edge against the "
                                               "reference's)",
                                               s.seamWeight, s.seamPairBudget)
                                 : "";
    const std::string checker = s.checkerWeight > 0.0
                                    ? fmt::format(" (plus {} x the checker term: the error of the response on +-1 checkerboards of "
                                                  "squares S/4 to S/32 texels, two phases each)",
                                                  s.checkerWeight)
                                    : "";
    const std::string tail =
        s.tailWeight > 0.0 ? fmt::format(" (each texel's L1 plus {} x |W - K|, its mass beyond {} texels of the lobe centre against the "
                                         "reference's)",
                                         s.tailWeight, kTailTexels)
                           : "";
    return fmt::format(
        "Ceres {}: {} on the weighted mean impulse L1{}{} over the stratified output texels{}, per level; "
        "levels with fewer stratified texels get up to {}x the iterations, in proportion; weight sum "
        "kept >= {} of its mean (penalty {}); start: best of lobe layout{}{}{}{}{}",
        CERES_VERSION_STRING, method, tail, checker, seam, s.roughIterationFactor, kMinWeightSum, kPenalty,
        s.fresh || (s.inits.empty() && s.bank.empty()) ? ", previous level" : ", previous level where nothing below offers a start",
        initDescription(s),
        s.starts > 1 ? fmt::format("; also fitted from {} importance layouts (FIS taps), the lowest objective kept", s.starts - 1) : "",
        screensStarts(s) ? "; every start runs Levenberg-Marquardt on the coarse texels, the lowest objective then the rest of the "
                           "solver (BFGS); a level without coarse texels runs every start through the whole solver"
                         : "",
        s.hops > 0 ? fmt::format("; then {} hops (the fit's taps moved at random and refitted, kept where the objective is lower)", s.hops)
                   : "");
}

// What decides between the fit and an exact --init: the exact mean L1 (over `judge`, the stratified
// texels measured exactly), plus the tail and checker terms (over the fit's texels) where they are on.
double fitScore(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels,
                const std::vector<OutputTexel>& judge, const CheckerTerm& checker) {
    const double l1 = evaluatePrepared(model, blocks, judge).error.mean;
    const double tail = model.tailWeight() > 0.0 ? model.tailWeight() * evaluatePrepared(model, blocks, texels).tailMean : 0.0;
    const double c = checker.weight > 0.0 ? checker.weight * meanCheckerError(model, blocks, texels, checker) : 0.0;
    return l1 + tail + c;
}

// Records level m: where `exact`, its exact L1 over `texels` (the judge: the stratified texels
// measured exactly) and with `all` over every texel; else, over the fit's own texels, only the lowest
// weight sum, which does not depend on how the L1 is measured. Returns the mean L1 over `texels`.
double recordLevel(TapTable& table, int m, const ImpulseModel& model, const std::vector<OutputTexel>& texels, bool exact, bool all) {
    TableLevel& level = table.levels[m];
    const LevelEvaluation stratified = evaluatePrepared(model, levelBlocks(table, m).data(), texels);
    level.minWeightSum = stratified.minWeightSum;
    if (!exact) return stratified.error.mean;
    level.stratified = stratified.error;
    if (!all) return stratified.error.mean;
    const LevelEvaluation every = evaluateLevel(table, m, TexelSet::all);
    level.all = every.error;
    level.minWeightSum = std::min(level.minWeightSum, every.minWeightSum);
    return stratified.error.mean;
}

// What every level's fit shares.
struct FitContext {
    const FitSettings& settings;
    const std::function<void(const FitProgress&)>& progress;
    Clock::time_point start;
    const ImpulseModel& model;
    const MomentBasis& basis;
    const ThreadShare& share;

    void report(int level, double value, std::string stage) const {
        if (progress) progress({level, 0, value, secondsSince(start), std::move(stage)});
    }
};

using Start = std::pair<std::string, std::vector<double>>;

// One level's fit: its start, the solver runs from it (and from the other starts), the hops, the
// --init kept aside, and the level's records.
class LevelFit {
public:
    LevelFit(const FitContext& context, TapTable& table, int m, const std::vector<OutputTexel>& texels,
             const std::vector<OutputTexel>& judge, const CheckerTerm& checker)
        : context_(context), settings_(context.settings), model_(context.model), table_(table), m_(m), alpha_(tableLevelAlpha(table, m)),
          level_(table.levels[m]), texels_(texels), judge_(judge), checker_(checker),
          blocks_(levelBlocks(table, m)), coarseChecker_{checker.basis, {}, checker.weight} {
        for (std::size_t n = 0; n < texels.size(); n += coarseStride(texels.size())) {
            coarse_.push_back(texels[n]);
            if (!checker.reference.empty()) coarseChecker_.reference.push_back(checker.reference[n]);
        }
    }

    // previous: the level fitted before this one, a start (-1: none); levelStart: when preparing the
    // texels began, which took kernelSeconds.
    void run(int previous, Clock::time_point levelStart, double kernelSeconds) {
        const std::vector<Start> starts = startsFrom(bestCandidate(previous));
        pairs_ = settings_.seamWeight > 0.0
                     ? prepareSeamPairs(settings_.faceSize, m_, tableLevelLobe(table_, m_), settings_.seamPairBudget, context_.basis)
                     : std::vector<SeamPair>{};
        // With several starts and lm-bfgs, every start runs the Levenberg-Marquardt part on the coarse
        // texels and only the lowest objective goes on (with --screen-all, another solver or on a cheap
        // level, every start runs in full and the lowest objective is kept: a cheap level's starts end
        // far apart, not in the order of their L1 at the start).
        const bool screen = starts.size() > 1 && settings_.solver == FitSolver::lmBfgs && !settings_.screenAll && !cheap();
        level_.coefficients = starts.front().second;
        reportTerms("at the start");
        double bestObjective = 1e300;
        std::vector<double> fitted;
        std::string bestName;
        for (const auto& [name, coefficients] : starts) {
            level_.coefficients = coefficients;
            const double value = screen ? screenStart() : fitInFull(starts.size() > 1);
            if (starts.size() > 1)
                context_.report(m_, value, fmt::format("objective after {} from {}", screen ? "Levenberg-Marquardt" : "the fit", name));
            if (value < bestObjective || fitted.empty()) {
                bestObjective = value;
                fitted = level_.coefficients;
                bestName = name;
            }
        }
        level_.coefficients = fitted;
        if (screen) {
            context_.report(m_, bestObjective, fmt::format("objective lowest after Levenberg-Marquardt: {} goes on", bestName));
            fitInFull(false, true);
        }
        hop();
        if (fallback_ && fitScore(model_, blocks_.data(), texels_, judge_, checker_) > fallback_->first) {
            level_.coefficients = fallback_->second;
            context_.report(m_, fallback_->first, "kept the exact --init");
        }
        reportTerms("after the fit");
        // Weights only matter relative to each other: scale them so the mean weight sum is 1.
        scaleWeights(table_, m_, 1.0 / weightedMeanWeightSum(model_, blocks_.data(), texels_));
        const bool exact = settings_.records != Records::none;
        const double l1 = recordLevel(table_, m_, model_, exact ? judge_ : texels_, exact, false);
        if (context_.progress) {
            FitProgress done{m_, report_.iterations, l1, secondsSince(context_.start), "done"};
            done.levelSeconds = secondsSince(levelStart);
            done.kernelSeconds = kernelSeconds;
            done.evaluationSeconds = modelSeconds_;
            done.solverSeconds = std::max(0.0, report_.solverSeconds - modelSeconds_);
            done.evaluations = evaluations_;
            context_.progress(done);
        }
        if (settings_.records == Records::all) {
            recordLevel(table_, m_, model_, judge_, true, true);
            context_.report(m_, level_.all.mean, "all texels");
        }
    }

private:
    double l1() const { return evaluatePrepared(model_, blocks_.data(), texels_).error.mean; }

    // The candidate with the lowest L1 among the lobe layout, the previous level, the bank and the
    // --init tables; an --init the table can express exactly is also kept aside (fallback_).
    std::vector<double> bestCandidate(int previous) {
        std::vector<Start> candidates;
        lobeLayout(table_, m_, alpha_);
        candidates.emplace_back("lobe layout", level_.coefficients);
        if (previous >= 0) {
            warmStartFromLevel(table_, m_, previous);
            candidates.emplace_back(fmt::format("level {}", previous), level_.coefficients);
        }
        if (!settings_.fresh && !settings_.bank.empty()) addBankCandidate(candidates);
        // An init table whose filter this table can express exactly (same form, or const into quad)
        // is kept aside: the fit keeps it where it cannot beat it, so more taps (or the quadratic
        // form) are never worse. With N/2 taps the fit starts from its taps split and moved apart
        // (the exact split sits at the init's stationary point). With --fresh they take no part.
        const std::size_t startInits = settings_.fresh ? 0 : settings_.inits.size();
        for (std::size_t i = 0; i < startInits; ++i) {
            const TapTable& init = settings_.inits[i];
            const std::string name = settings_.inits.size() > 1 ? fmt::format("--init {}", i + 1) : "--init";
            startFromTable(table_, m_, init);
            if (init.form == settings_.form || init.form == TableForm::constant) {
                const double score = fitScore(model_, blocks_.data(), texels_, judge_, checker_);
                context_.report(m_, score, fmt::format("start {} (exact, kept aside)", name));
                if (!fallback_ || score < fallback_->first) fallback_.emplace(score, level_.coefficients);
            }
            if (init.taps != settings_.taps) startFromTable(table_, m_, init, kSplitSpread);
            candidates.emplace_back(name, level_.coefficients);
        }
        double best = 1e300;
        std::vector<double> bestCoefficients;
        for (auto& [name, coefficients] : candidates) {
            level_.coefficients = coefficients;
            const double value = l1();
            context_.report(m_, value, "start " + name);
            if (value < best) {
                best = value;
                bestCoefficients = coefficients;
            }
        }
        return bestCoefficients;
    }

    // The bank: each table's level of the nearest roughness (within a factor of 2 in alpha), screened
    // on every 8th stratified texel; the best joins the candidates.
    void addBankCandidate(std::vector<Start>& candidates) {
        std::vector<OutputTexel> screen;
        for (std::size_t n = 0; n < texels_.size(); n += kBankScreenStride) screen.push_back(texels_[n]);
        std::vector<std::pair<double, Start>> screened;
        for (const FitSettings::BankTable& bank : settings_.bank) {
            const int from = nearestLevel(bank.table, alpha_);
            if (from < 0) continue;
            startFromBank(table_, m_, bank.table, from);
            const double value = evaluatePrepared(model_, blocks_.data(), screen).error.mean;
            screened.emplace_back(value, Start{fmt::format("bank {} level {}", bank.name, from), level_.coefficients});
        }
        std::ranges::stable_sort(screened, {}, [](const auto& s) { return s.first; });
        if (screened.empty()) return;
        candidates.push_back(std::move(screened.front().second));
        for (std::size_t n = 1; n < screened.size() && n < static_cast<std::size_t>(settings_.bankStarts); ++n)
            bankStarts_.push_back(std::move(screened[n].second));
    }

    // The best candidate and, with --starts K > 1, K - 1 importance layouts (turned apart about the axis).
    std::vector<Start> startsFrom(const std::vector<double>& best) {
        std::vector<Start> starts{{"best start", best}};
        for (Start& s : bankStarts_) starts.push_back(std::move(s));
        for (int k = 0; k + 1 < settings_.starts; ++k) {
            const double rotation = 2.0 * std::numbers::pi * k / ((settings_.starts - 1) * settings_.taps);
            importanceLayout(table_, m_, alpha_, rotation);
            const std::string name = fmt::format("importance layout {}", k + 1);
            context_.report(m_, l1(), "start " + name);
            starts.emplace_back(name, level_.coefficients);
        }
        return starts;
    }

    // Hops: refits from the best fit so far, moved at random; a hop that lowers the objective is kept.
    void hop() {
        if (settings_.hops <= 0) return;
        double current = solve(texels_, 0, 0, true);
        for (int k = 0; k < settings_.hops; ++k) {
            const std::vector<double> kept = level_.coefficients;
            hopLayout(table_, m_, alpha_, static_cast<unsigned>(1000 * m_ + k));
            const double value = fitInFull(true);
            context_.report(m_, value, fmt::format("objective after hop {}", k + 1));
            if (value < current) current = value;
            else level_.coefficients = kept;
        }
    }

    // The solver from the level's coefficients: Levenberg-Marquardt; BFGS with the frames tied (the
    // frame of the lowest L1 copied into the others) on the coarse texels: cheap iterations that carry
    // the fit most of the way down a slow slope with a third of the parameters, so that neither the
    // frames settle in different basins nor the fit follows the few coarse texels; then BFGS on every
    // texel, each frame free. A cheap level (no coarse texels) runs Levenberg-Marquardt and BFGS on
    // every texel, its frames free: tying them helps some such levels and not others. Returns the
    // objective at the end where `compare` (one more evaluation). A `screened` start has run its
    // Levenberg-Marquardt on the coarse texels: it goes on to the tied BFGS.
    double fitInFull(bool compare, bool screened = false) {
        const int lm = levelIterations(settings_, lmPart(settings_), texels_.size()),
                  bfgs = levelIterations(settings_, bfgsPart(settings_), texels_.size());
        if (settings_.coarseIterations == 0 || cheap()) return solve(texels_, lm, bfgs, compare);
        if (!screened) solve(texels_, lm, 0);
        if (settings_.solver != FitSolver::lm) {
            tieFrames();
            solve(coarse_, 0, levelIterations(settings_, settings_.coarseIterations, texels_.size()), false, true);
        }
        return solve(texels_, 0, bfgs, compare);
    }

    // A level without coarse texels: fewer than twice kCoarseTexels stratified texels (the rough
    // levels, a few dozen texels each).
    bool cheap() const { return coarse_.size() == texels_.size(); }

    // Every frame gets the taps of the frame whose copy has the lowest L1.
    void tieFrames() {
        const std::vector<double> fitted = level_.coefficients;
        double best = 1e300;
        std::vector<double> tied;
        for (int f = 0; f < kFrameCount; ++f) {
            level_.coefficients = fitted;
            oneFrameLayout(table_, m_, f);
            const double value = l1();
            if (value < best) {
                best = value;
                tied = level_.coefficients;
            }
        }
        level_.coefficients = tied;
        context_.report(m_, best, "frames tied");
    }

    // A start's screening: the Levenberg-Marquardt part on the coarse texels, as many iterations at
    // every level (it only ranks the starts); returns the objective there.
    double screenStart() { return solve(coarse_, lmPart(settings_), 0, true); }

    // Runs lmIterations of Levenberg-Marquardt, then bfgsIterations of BFGS, over `texels` from the
    // level's coefficients; returns the objective at the end where `compare` (one more evaluation).
    // With `tied`, the BFGS keeps every frame's taps the same (those of frame 0).
    double solve(const std::vector<OutputTexel>& texels, int lmIterations, int bfgsIterations, bool compare = false, bool tied = false) {
        const LevelObjective objective(model_, texels, weightedMeanWeightSum(model_, blocks_.data(), texels), pairs_, context_.basis,
                                       settings_.seamWeight, &texels == &coarse_ ? coarseChecker_ : checker_, context_.share);
        if (lmIterations > 0 && settings_.solver != FitSolver::bfgs) {
            ProgressCallback callback(context_.progress, m_, context_.start, 2.0);
            std::vector<double*> blocks;
            for (const double* b : blocks_) blocks.push_back(const_cast<double*>(b));
            add(solveLevenbergMarquardt(model_, objective, blocks, lmIterations, callback));
        }
        if (bfgsIterations > 0 && settings_.solver != FitSolver::lm) {
            ProgressCallback callback(context_.progress, m_, context_.start, 1.0);
            add(solveBfgs(model_, objective, level_.coefficients.data(), bfgsIterations, callback, tied));
            if (tied) oneFrameLayout(table_, m_, 0);
        }
        const double value = compare ? objective.value(blocks_.data()) : 0.0;
        modelSeconds_ += objective.seconds();
        evaluations_ += objective.evaluations();
        return value;
    }

    void add(const SolveReport& r) {
        report_.iterations += r.iterations;
        report_.solverSeconds += r.solverSeconds;
    }

    // The seam and checker terms' means, where they are on.
    void reportTerms(const char* when) const {
        if (!pairs_.empty() && context_.progress) {
            std::vector<double> scratch;
            double sum = 0.0;
            for (const SeamPair& pair : pairs_) sum += seamError(model_, blocks_.data(), pair, context_.basis, nullptr, scratch);
            context_.report(m_, sum / static_cast<double>(pairs_.size()), fmt::format("seam term {}", when));
        }
        if (checker_.weight > 0.0 && context_.progress)
            context_.report(m_, meanCheckerError(model_, blocks_.data(), texels_, checker_), fmt::format("checker term {}", when));
    }

    const FitContext& context_;
    const FitSettings& settings_;
    const ImpulseModel& model_;
    TapTable& table_;
    int m_;
    double alpha_;
    TableLevel& level_;
    const std::vector<OutputTexel>& texels_;
    const std::vector<OutputTexel>& judge_;
    const CheckerTerm& checker_;
    const std::vector<const double*> blocks_; // into level_.coefficients, whose storage stays put
    std::vector<SeamPair> pairs_;
    std::vector<OutputTexel> coarse_; // every few of texels_: at least kCoarseTexels of them
    CheckerTerm coarseChecker_;       // the checker term's references of coarse_
    std::vector<Start> bankStarts_;
    std::optional<std::pair<double, std::vector<double>>> fallback_;
    SolveReport report_;
    double modelSeconds_ = 0.0;
    int evaluations_ = 0;
};

} // namespace

bool screensStarts(const FitSettings& settings) {
    const bool bankStarts = settings.bankStarts > 1 && settings.bank.size() > 1 && !settings.fresh;
    return (settings.starts > 1 || bankStarts) && settings.solver == FitSolver::lmBfgs && !settings.screenAll;
}

std::size_t coarseTexelCount(std::size_t texels) {
    const std::size_t stride = coarseStride(texels);
    return (texels + stride - 1) / stride;
}

double levelIterationCost(const FitSettings& s, std::size_t texels) {
    const double share = static_cast<double>(coarseTexelCount(texels)) / static_cast<double>(std::max<std::size_t>(1, texels));
    // The whole solver from one start (fitInFull), and what a screened start runs after its screening.
    const double lm = s.solver == FitSolver::bfgs ? 0 : levelIterations(s, lmPart(s), texels);
    // The tied BFGS on the coarse texels; a cheap level (without them) has none and screens no start.
    const bool cheap = share >= 1.0;
    const bool coarse = s.solver != FitSolver::lm && s.coarseIterations > 0 && !cheap;
    double whole = lm + levelIterations(s, bfgsPart(s), texels);
    if (coarse) whole += share * levelIterations(s, s.coarseIterations, texels);
    const double afterScreening = coarse ? whole - lm : whole;
    const bool bank = s.bank.size() > 1 && !s.fresh;
    const int starts = std::max(1, s.starts) + (bank ? std::min(s.bankStarts, static_cast<int>(s.bank.size())) - 1 : 0);
    if (screensStarts(s) && !cheap) return starts * share * lmPart(s) + afterScreening + s.hops * whole;
    return starts * whole + s.hops * whole;
}

int levelIterations(const FitSettings& settings, int iterations, std::size_t texels) {
    const double budget = settings.stratifiedBudget;
    const double factor = std::clamp(budget / std::max<double>(1.0, static_cast<double>(texels)), 1.0,
                                     static_cast<double>(std::max(1, settings.roughIterationFactor)));
    return static_cast<int>(std::lround(iterations * factor));
}

FitSolver parseFitSolver(const std::string& name) {
    if (name == "lm-bfgs") return FitSolver::lmBfgs;
    if (name == "bfgs") return FitSolver::bfgs;
    if (name == "lm") return FitSolver::lm;
    throw ProbeError(fmt::format("'{}' is none of lm-bfgs, bfgs, lm", name));
}

bool copiesInitRecords(const FitSettings& settings, int m) {
    if (settings.fitLevels.empty() || settings.inits.empty() || std::ranges::find(settings.fitLevels, m) != settings.fitLevels.end())
        return false;
    // The exact measure of a level costs seconds at 512^2: a per-level job pays for its own level alone.
    const TapTable& init = settings.inits.front();
    if (init.faceSize != settings.faceSize || init.levelCount != settings.levelCount || init.taps != settings.taps ||
        init.form != settings.form || init.stratifiedBudget != settings.stratifiedBudget)
        return false;
    const TableLevel& level = init.levels[static_cast<std::size_t>(m)];
    if (settings.records == Records::none) return true;
    return level.stratified.mean >= 0.0 && (settings.records != Records::all || level.all.mean >= 0.0);
}

bool levelFinished(const TableLevel& level) { return level.stratified.mean >= 0.0 || level.minWeightSum != 0.0; }

namespace {

void checkFitSettings(const FitSettings& settings, const TapTable& table) {
    for (const TapTable& init : settings.inits) {
        if (init.lobe != settings.lobe)
            throw ProbeError(fmt::format("--init: table is fitted for the {} lobe, not {}", lobeName(init.lobe), lobeName(settings.lobe)));
        if (init.faceSize != settings.faceSize || init.levelCount != settings.levelCount)
            throw ProbeError(fmt::format("--init: table is for face size {} with {} levels, not {} with {}", init.faceSize, init.levelCount,
                                         settings.faceSize, settings.levelCount));
        if (init.taps != settings.taps && init.taps * 2 != settings.taps)
            throw ProbeError(
                fmt::format("--init: table has {} taps per frame, expected {} or {}", init.taps, settings.taps, settings.taps / 2));
    }
    if (!settings.fitLevels.empty()) {
        if (settings.inits.empty() || settings.inits.front().taps != settings.taps || settings.inits.front().form != settings.form)
            throw ProbeError("--fit-levels: the first --init must have the table's taps and form (the other levels are copied from it)");
        for (int m : settings.fitLevels)
            if (m < 0 || m >= settings.levelCount)
                throw ProbeError(fmt::format("--fit-levels: level {} is not one of 0..{}", m, settings.levelCount - 1));
    }
    if (settings.fresh && settings.fitLevels.empty())
        throw ProbeError("--fresh: needs --fit-levels (the --init supplies the other levels)");
    if (const TapTable* r = settings.resume;
        r && (r->faceSize != table.faceSize || r->levelCount != table.levelCount || r->taps != table.taps || r->form != table.form ||
              r->mapping != table.mapping || r->lobe != table.lobe || !(r->pyramid == table.pyramid) ||
              r->stratifiedBudget != table.stratifiedBudget || r->solver != table.solver))
        throw ProbeError("--resume: the checkpoint was written by a fit of another shape or solver settings");
}

// What becomes of a level: nothing (alpha 0), taken from the checkpoint, copied with the first
// --init's records, copied and measured, or fitted.
enum class LevelWork { none, resumed, copiedRecords, copied, fitted };

LevelWork levelWork(const FitSettings& settings, const TapTable& table, int m) {
    if (tableLevelAlpha(table, m) <= 0.0) return LevelWork::none;
    if (settings.resume && levelFinished(settings.resume->levels[m])) return LevelWork::resumed;
    if (copiesInitRecords(settings, m)) return LevelWork::copiedRecords;
    if (!settings.fitLevels.empty() && std::ranges::find(settings.fitLevels, m) == settings.fitLevels.end()) return LevelWork::copied;
    return LevelWork::fitted;
}

// Whether a fitted level starts from the level fitted before it: only where neither the bank nor an
// --init offers a start, so that the levels that have one are fitted at once, in any order.
bool startsFromPreviousLevel(const FitSettings& settings, const TapTable& table, int m) {
    if (settings.fresh) return true;
    if (!settings.inits.empty()) return false;
    const double alpha = tableLevelAlpha(table, m);
    return std::ranges::none_of(settings.bank, [&](const FitSettings::BankTable& b) { return nearestLevel(b.table, alpha) >= 0; });
}

} // namespace

TapTable fitTable(const FitSettings& settings, const std::function<void(const FitProgress&)>& progress,
                  const std::function<void(const TapTable&)>& levelDone) {
    TapTable table = emptyTable(settings.faceSize, settings.levelCount, settings.taps, settings.form, settings.mapping, settings.pyramid);
    table.lobe = settings.lobe;
    table.stratifiedBudget = settings.stratifiedBudget;
    table.solver = solverDescription(settings);
    // A partial refit names the levels it fitted and keeps the provenance of those it copied.
    if (!settings.fitLevels.empty() && !settings.inits.empty())
        table.solver = fmt::format("levels {}: {}; the other levels copied from the first --init: [{}]",
                                   fmt::join(settings.fitLevels, ", "), table.solver, settings.inits.front().solver);
    table.seamWeight = settings.seamWeight;
    checkFitSettings(settings, table);
    const auto start = Clock::now();
    const ImpulseModel model(settings.faceSize, settings.pyramid, settings.taps, settings.form, settings.tailWeight);
    // The seam term's basis (half a GiB at 1024^2): only where the term is on.
    const MomentBasis basis = settings.seamWeight > 0.0 ? MomentBasis(settings.faceSize, settings.pyramid) : MomentBasis();
    const std::optional<MomentBasis> checkers =
        settings.checkerWeight > 0.0
            ? std::optional<MomentBasis>(std::in_place, settings.faceSize, settings.pyramid, MomentFunctions::checkers)
            : std::nullopt;
    // The base's geometry, for the exact measure of the stratified texels where the fit measures cells:
    // what judges a level (its records, the kept --init) is the exact L1, whatever the fit measures.
    const bool judged = settings.records != Records::none || !settings.inits.empty();
    const std::optional<CubeGeometry> geometry =
        settings.measure == Measure::cells && judged ? std::optional<CubeGeometry>(std::in_place, settings.faceSize) : std::nullopt;

    // Progress, the finished levels (what levelDone sees: a level is there once it is finished) and
    // the chains' threads are shared by levels fitted at once.
    std::mutex mutex;
    const std::function<void(const FitProgress&)> reportLocked = [&](const FitProgress& p) {
        const std::lock_guard lock(mutex);
        if (progress) progress(p);
    };
    ThreadShare share;
    share.threads = omp_get_max_threads();
    const FitContext context{settings, reportLocked, start, model, basis, share};
    TapTable finished = table;
    auto finish = [&](int m, bool done) {
        const std::lock_guard lock(mutex);
        finished.levels[m] = table.levels[m];
        if (done && levelDone) levelDone(finished);
    };

    // Chains of levels, each one after the other within a chain: a level joins the chain of the
    // level before it where it starts from that level's fit. The chains run at once.
    std::vector<LevelWork> work(static_cast<std::size_t>(settings.levelCount));
    std::vector<std::vector<int>> chains;
    std::vector<int> previousOf(work.size(), -1);
    int previous = -1;
    for (int m = 0; m < settings.levelCount; ++m) {
        work[m] = levelWork(settings, table, m);
        if (work[m] == LevelWork::none) continue;
        if (work[m] == LevelWork::fitted && startsFromPreviousLevel(settings, table, m)) previousOf[m] = previous;
        // (a resumed level or one copied with its records is there from the start)
        const bool follows = previousOf[m] >= 0 && (work[previous] == LevelWork::copied || work[previous] == LevelWork::fitted);
        if (work[m] == LevelWork::resumed || work[m] == LevelWork::copiedRecords) {
            table.levels[m] = work[m] == LevelWork::resumed ? settings.resume->levels[m] : settings.inits.front().levels[m];
            context.report(m, table.levels[m].stratified.mean, work[m] == LevelWork::resumed ? "resumed" : "copied from --init");
            finish(m, work[m] == LevelWork::copiedRecords);
        } else if (follows) {
            std::ranges::find_if(chains, [&](const std::vector<int>& c) { return c.back() == previous; })->push_back(m);
        } else {
            chains.push_back({m});
        }
        previous = m;
    }

    auto runLevel = [&](int m) {
        const LevelLobe lobe = tableLevelLobe(table, m);
        const auto kernelStart = Clock::now();
        const std::vector<WeightedTexel> stratified = stratifiedTexels(settings.faceSize >> m, settings.stratifiedBudget);
        const std::vector<OutputTexel> texels =
            prepareTexels(stratified, settings.faceSize, m, lobe, settings.tailWeight > 0.0, settings.measure);
        const std::vector<OutputTexel> measured = geometry ? measuredTexels(*geometry, m, lobe, stratified) : std::vector<OutputTexel>{};
        const std::vector<OutputTexel>& judge = measured.empty() ? texels : measured;
        const CheckerTerm checker = checkers ? prepareCheckerTerm(texels, *checkers, settings.checkerWeight) : CheckerTerm{basis, {}, 0.0};
        const double kernelSeconds = secondsSince(kernelStart);
        if (work[m] == LevelWork::copied) {
            startFromTable(table, m, settings.inits.front());
            const bool exact = settings.records != Records::none;
            context.report(m, recordLevel(table, m, model, exact ? judge : texels, exact, settings.records == Records::all),
                           "copied from --init");
        } else {
            LevelFit(context, table, m, texels, judge, checker).run(previousOf[m], kernelStart, kernelSeconds);
        }
        finish(m, true);
    };
    // Every thread on one chain at a time, the chains not yet finished sharing the threads on their
    // levels' texels (ThreadShare); the results do not depend on how the threads are shared.
    share.chainsLeft = static_cast<int>(chains.size());
    const int concurrent = std::max(1, std::min(share.threads, static_cast<int>(chains.size())));
    omp_set_max_active_levels(2);
#pragma omp parallel for schedule(dynamic, 1) num_threads(concurrent)
    for (std::size_t c = 0; c < chains.size(); ++c) {
        omp_set_num_threads(share.now());
        for (const int m : chains[c]) runLevel(m);
        --share.chainsLeft;
    }
    omp_set_max_active_levels(1);
    table.fitSeconds = secondsSince(start);
    return table;
}

} // namespace probefit
