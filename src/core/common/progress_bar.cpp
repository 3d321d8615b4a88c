#include "core/common/progress_bar.h"

#include <unistd.h>

#include <algorithm>

namespace icgm {

ProgressBar::ProgressBar(size_t total, std::string label, std::FILE* out)
    : total_(total), label_(std::move(label)), out_(out), tty_(isatty(fileno(out)) != 0) {
  start_ = last_draw_ = std::chrono::steady_clock::now();
}

void ProgressBar::Update(size_t done) {
  const auto now = std::chrono::steady_clock::now();
  if (tty_) {
    if (now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    Draw(done, false);
  } else {
    const int decile = total_ ? static_cast<int>(10 * std::min(done, total_) / total_) : 0;
    if (decile == last_decile_) return;
    last_decile_ = decile;
    Draw(done, false);
  }
}

void ProgressBar::Finish() { Finish(total_); }

void ProgressBar::Finish(size_t done) {
  if (finished_) return;
  finished_ = true;
  Draw(done, true);
}

void ProgressBar::Draw(size_t done, bool final_draw) {
  constexpr int kWidth = 30;
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total_ ? std::min(1.0, static_cast<double>(done) / total_) : 1.0;
  const int filled = static_cast<int>(frac * kWidth);
  std::string bar(kWidth, ' ');
  for (int i = 0; i < filled; ++i) bar[i] = '=';
  if (filled < kWidth) bar[filled] = '>';
  const double rate = elapsed_s > 0 ? done / elapsed_s : 0.0;
  const double eta_s = rate > 0 ? (total_ - std::min(done, total_)) / rate : 0.0;
  std::fprintf(out_, "%s%s [%s] %zu/%zu %3d%%  %.1f/s  %s %.0fs%s", tty_ ? "\r" : "",
               label_.c_str(), bar.c_str(), done, total_, static_cast<int>(100 * frac), rate,
               final_draw ? "took" : "ETA", final_draw ? elapsed_s : eta_s,
               (final_draw || !tty_) ? "\n" : "");
  std::fflush(out_);
}

}  // namespace icgm
