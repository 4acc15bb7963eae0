#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

namespace pbdsplat::core {

class Stopwatch {
public:
    Stopwatch() : start_(clock::now()) {}
    void restart() { start_ = clock::now(); }
    double elapsed_ms() const { return std::chrono::duration<double, std::milli>(clock::now() - start_).count(); }

private:
    using clock = std::chrono::steady_clock;
    clock::time_point start_;
};

// Median of a sample set (by copy: benchmarks keep their raw samples for the report).
inline double median(std::vector<double> samples) {
    if (samples.empty()) return 0.0;
    const size_t mid = samples.size() / 2;
    std::nth_element(samples.begin(), samples.begin() + long(mid), samples.end());
    double m = samples[mid];
    if (samples.size() % 2 == 0) {
        m = 0.5 * (m + *std::max_element(samples.begin(), samples.begin() + long(mid)));
    }
    return m;
}

// Mean of a sample set: what a pass that works one frame in several costs over the run.
inline double mean(const std::vector<double>& samples) {
    if (samples.empty()) return 0.0;
    double sum = 0.0;
    for (double v : samples) sum += v;
    return sum / double(samples.size());
}

} // namespace pbdsplat::core
