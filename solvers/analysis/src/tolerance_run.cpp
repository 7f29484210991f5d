#include "ltca/analysis/tolerance_run.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

namespace ltca::analysis {

int ResolveThreads(int requested) {
  if (requested < 0 || requested > kMaxToleranceThreads) {
    throw std::invalid_argument(
        fmt::format("--threads {}: expected 0 (every hardware thread) or 1 to {}", requested, kMaxToleranceThreads));
  }
  return requested > 0 ? requested : std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, kMaxToleranceThreads);
}

void ToleranceRunPlan::Validate(const ToleranceSettings& settings) const {
  if (first > std::numeric_limits<std::int64_t>::max() - settings.samples) {
    throw std::invalid_argument(fmt::format("--first {} with {} samples: the last sample index would pass {}", first, settings.samples,
                                            std::numeric_limits<std::int64_t>::max()));
  }
}

ToleranceResult RunToleranceStudy(const ToleranceStudy& study, const ToleranceRunPlan& plan) {
  using Clock = std::chrono::steady_clock;
  const ToleranceSettings& settings = study.settings();
  ToleranceResult result;
  result.first = plan.first;
  result.samples = settings.samples;
  result.threads = plan.threads;
  result.rank = plan.ranks != nullptr ? plan.ranks->rank() : 0;
  result.ranks = plan.ranks != nullptr ? plan.ranks->size() : 1;
  const std::int64_t n = settings.samples;
  plan.Validate(settings);
  const bool root = result.rank == 0;
  ToleranceProgress none;
  ToleranceProgress& progress = plan.progress != nullptr ? *plan.progress : none;

  // Rank r runs the r-th static block of the samples on its threads: rank 0 keeps its own and,
  // after the gather, the others' in rank order (so in sample order); another rank sends its
  // samples as bytes.
  const std::int64_t begin = plan.first + n * result.rank / result.ranks, end = plan.first + n * (result.rank + 1) / result.ranks;
  result.table = SampleTable(plan.first);
  if (root) result.table.Reserve(n);
  std::string mine;
  const auto keep = [&](const ToleranceSample& s) {
    if (!root) {
      result.rank_succeeded = result.rank_succeeded && s.status == RunStatus::kSuccess;
      return AppendSampleBytes(s, mine);
    }
    if (plan.sink) plan.sink(s);
    result.table.Add(s);
  };
  // The estimate of the whole run: the first samples (two a thread) warm the caches (the flank
  // compliance, the threads' runners and buffers) and are left out of the rate; the rest run in one
  // stream, and once 0.5 s has passed since the warm-up or a twentieth of the samples is done, the
  // samples left are estimated at the rate since the warm-up. A run done before that gets no
  // estimate. The samples depend on (seed, i) only, so the split changes no number.
  const auto start = Clock::now();
  {
    const std::int64_t count = end - begin;
    const auto threads = static_cast<std::int64_t>(std::max(1, plan.threads));
    const std::int64_t warm = std::min<std::int64_t>(count, 2 * threads);
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    progress.Start(TolerancePhase::kSamples, count);
    study.RunStream(begin, warm, plan.threads, keep, [&](std::int64_t done) { progress.Update(TolerancePhase::kSamples, done); });
    const auto warmed = Clock::now();
    bool estimated = !root;
    study.RunStream(begin + warm, count - warm, plan.threads, keep, [&](std::int64_t k) {
      progress.Update(TolerancePhase::kSamples, warm + k);
      if (estimated || k <= 0 || warm + k >= count) return;
      const double rate_seconds = since(warmed);
      if (rate_seconds < 0.5 && 20 * (warm + k) < count) return;
      estimated = true;
      progress.Estimate(since(start) + rate_seconds / static_cast<double>(k) * static_cast<double>(count - warm - k), warm + k, count);
    });
    progress.Finish(TolerancePhase::kSamples);
  }
  if (plan.ranks != nullptr && result.ranks > 1) {
    const std::vector<std::string> parts = plan.ranks->Gather(mine);
    if (!root) return result;
    for (std::size_t r = 1; r < parts.size(); ++r) ReadSampleBytes(parts[r], study, keep);
    if (result.table.size() != n) throw std::runtime_error(fmt::format("tolerance: gathered {} samples, expected {}", result.table.size(), n));
  }
  result.sample_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  result.summary = Summarise(study, result.table);

  const auto worst_start = Clock::now();
  if (plan.worst_case) {
    // At most 1 + 2 x columns + 2 x figures runs (a figure with no stack runs no corner).
    progress.Start(TolerancePhase::kWorstCase, 1 + 2 * static_cast<std::int64_t>(study.inputs().size() + kToleranceFigureCount));
    result.worst_case = ExtremeValueWorstCase(study, plan.threads, [&](std::int64_t done, std::int64_t) {
      progress.Update(TolerancePhase::kWorstCase, done);
    });
    progress.Finish(TolerancePhase::kWorstCase);
    result.beyond = CompareWithCorners(study, result.table, *result.worst_case);
  }
  result.worst_case_seconds = std::chrono::duration<double>(Clock::now() - worst_start).count();

  // The chains' closing links, by the extreme-value method and by Monte Carlo over the study's
  // sample count and seed (Jiang 2022 section 5.1).
  for (std::size_t c = 0; c < settings.chains.size(); ++c) {
    const DimensionChain& chain = settings.chains[c];
    result.chains.push_back({chain.name, ExtremeValueClosingLink(chain.links), ChainMonteCarlo(chain.links, n, settings.seed, c)});
  }
  return result;
}

}  // namespace ltca::analysis
