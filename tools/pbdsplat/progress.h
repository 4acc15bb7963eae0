#pragma once
// Progress of a long command on stderr, so a user sees it is alive within a few seconds.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/timer.h"

namespace pbdsplat::cli {

// Frames done, rate and time left: a bar on a terminal, a line every few seconds otherwise (a
// log or a pipe still shows the run is alive).
// `total` 0: not known in advance (frames done and rate only).
class Progress {
public:
    // `unit`: what is counted ("frames", "spacings", ...).
    Progress(std::string what, uint32_t total, std::string unit = "frames")
        : what_(std::move(what)), unit_(std::move(unit)), total_(total), tty_(isatty(STDERR_FILENO) != 0) {}
    // --quiet: no progress at all (main takes the flag for every command).
    static void set_quiet(bool q) { quiet() = q; }

    void frame_done(uint32_t done) {
        if (quiet()) return;
        const double elapsed = clock_.elapsed_ms() / 1000.0;
        const double rate = done / std::max(elapsed, 1e-6);
        if (total_ == 0) {
            if (elapsed - last_line_ >= 2.0) {
                std::fprintf(stderr, "%s: %u %s, %.1f per s%s", what_.c_str(), done, unit_.c_str(), rate, tty_ ? "\r" : "\n");
                std::fflush(stderr);
                last_line_ = elapsed;
            }
            return;
        }
        const double left = (total_ - done) / std::max(rate, 1e-9);
        if (tty_) {
            constexpr int width = 30;
            const int filled = int(double(done) / double(total_) * width);
            std::fprintf(stderr, "\r[%.*s%*s] %u/%u %s, %.1f per s, %.0f s left ", filled, "##############################",
                         width - filled, "", done, total_, unit_.c_str(), rate, left);
            if (done == total_) std::fputc('\n', stderr);
        } else if (elapsed - last_line_ >= 2.0 || done == total_) {
            std::fprintf(stderr, "%s: %u/%u %s, %.1f per s, %.0f s left\n", what_.c_str(), done, total_, unit_.c_str(), rate, left);
            last_line_ = elapsed;
        }
        std::fflush(stderr);
    }

private:
    static bool& quiet() {
        static bool q = false;
        return q;
    }
    std::string what_, unit_;
    uint32_t total_;
    bool tty_;
    core::Stopwatch clock_;
    double last_line_ = 0.0;
};

} // namespace pbdsplat::cli
