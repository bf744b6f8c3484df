// Progress on stderr: a bar with ETA on a terminal, a plain percentage line every 10%
// otherwise, nothing under --quiet.
#pragma once
#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace wmlt {

class Progress {
public:
    explicit Progress(bool quiet) : quiet_(quiet), tty_(isatty(2)), start_(std::chrono::steady_clock::now()) {}
    void update(double fraction) {
        if (quiet_) return;
        double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        int pct = int(fraction * 100.0);
        if (tty_) {
            if (t - lastDraw_ < 0.1 && fraction < 1.0) return;
            lastDraw_ = t;
            int filled = int(fraction * 40.0);
            char bar[41];
            for (int i = 0; i < 40; ++i) bar[i] = i < filled ? '=' : ' ';
            bar[40] = 0;
            double eta = fraction > 0 ? t / fraction - t : 0;
            std::fprintf(stderr, "\r[%s] %3d%%  %6.1fs  ETA %6.1fs", bar, pct, t, eta);
        } else if (pct / 10 > lastDecile_) {
            lastDecile_ = pct / 10;
            std::fprintf(stderr, "%d%% (%.1f s)\n", lastDecile_ * 10, t);
        }
    }
    void finish() {
        if (!quiet_ && tty_) std::fprintf(stderr, "\n");
    }

private:
    bool quiet_, tty_;
    std::chrono::steady_clock::time_point start_;
    double lastDraw_ = -1;
    int lastDecile_ = 0;
};

}  // namespace wmlt
