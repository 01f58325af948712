#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

namespace nhc::cli {

ProgressBar::ProgressBar(double t0, double t1, bool enabled)
    : t0_(t0), t1_(t1), enabled_(enabled && isatty(STDERR_FILENO) == 1), start_(Clock::now()), last_draw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double t) {
  if (!enabled_) return;
  const auto now = Clock::now();
  if (now - start_ < std::chrono::seconds(1)) return;
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  drawn_ = true;
  const double fraction = t1_ > t0_ ? std::clamp((t - t0_) / (t1_ - t0_), 0.0, 1.0) : 1.0;
  constexpr int width = 40;
  const int filled = static_cast<int>(fraction * width);
  char bar[width + 1];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '=' : (i == filled ? '>' : ' ');
  bar[width] = '\0';
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r[%s] %5.1f%%  t = %-12.6g %6.1f s", bar, 100 * fraction, t, elapsed);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r%*s\r", 80, "");
  std::fflush(stderr);
  drawn_ = false;
}

runtime::ProgressCallback terminal_progress() {
  auto bar = std::make_shared<std::optional<ProgressBar>>();
  return [bar](const runtime::Progress& p) {
    if (p.finished) {
      bar->reset();  // erases it
      return;
    }
    if (!*bar) bar->emplace(p.t_start, p.t_end, true);
    (*bar)->update(p.t);
  };
}

}  // namespace nhc::cli
