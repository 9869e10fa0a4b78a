#pragma once
// Console reporter that also keeps each benchmark's median real time, so a run can end with a table of
// candidate vs baseline medians and their ratio (benchmarks named <group>/<method>/<args...>).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>

namespace de_bench {

class RatioReporter : public benchmark::ConsoleReporter {
public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      // Without the time type ("/process_time", "/real_time"): a candidate timed over the whole process (its
      // CPU time summed over threads) still meets its baseline.
      benchmark::BenchmarkName key = run.run_name;
      key.time_type.clear();
      const std::string name = key.str();
      const double unit = toMicroseconds(run.time_unit);
      const Times times{run.GetAdjustedRealTime() * unit, run.GetAdjustedCPUTime() * unit};
      if (run.run_type == Run::RT_Aggregate) {
        if (run.aggregate_name == "median") medians_[name] = times;
      } else if (!aggregated_.count(name)) {
        medians_[name] = times;  // no repetitions: the single measurement
      }
      if (run.run_type == Run::RT_Aggregate) aggregated_[name] = true;
    }
  }

  /// For every benchmark whose name contains "/<candidate>/", the one with "/<baseline>/" instead.
  void printRatios(const std::string& candidate, const std::string& baseline) const {
    // Real and CPU medians: on a shared, oversubscribed machine the CPU time is the steadier measure.
    std::printf("\n%-44s %12s %12s %7s %12s %12s %7s\n", "benchmark (medians, us)", (candidate + " real").c_str(),
                (baseline + " real").c_str(), "ratio", (candidate + " cpu").c_str(), (baseline + " cpu").c_str(),
                "ratio");
    for (const auto& [name, time] : medians_) {
      const auto at = name.find("/" + candidate + "/");
      if (at == std::string::npos) continue;
      std::string other = name;
      other.replace(at + 1, candidate.size(), baseline);
      const auto match = medians_.find(other);
      if (match == medians_.end()) continue;
      std::printf("%-44s %12.3f %12.3f %6.1fx %12.3f %12.3f %6.1fx\n", name.c_str(), time.real, match->second.real,
                  match->second.real / time.real, time.cpu, match->second.cpu, match->second.cpu / time.cpu);
    }
  }

private:
  static double toMicroseconds(benchmark::TimeUnit unit) {
    switch (unit) {
      case benchmark::kNanosecond: return 1e-3;
      case benchmark::kMicrosecond: return 1.0;
      case benchmark::kMillisecond: return 1e3;
      case benchmark::kSecond: return 1e6;
    }
    return 1.0;
  }
  struct Times {
    double real, cpu;
  };
  std::map<std::string, Times> medians_;
  std::map<std::string, bool> aggregated_;
};

}  // namespace de_bench
