#include "visfield/render/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>

namespace vf {
namespace {

constexpr std::int64_t kRedrawIntervalMs = 100;
constexpr int kBarWidth = 30;

}  // namespace

ProgressBar::ProgressBar(std::string label, std::size_t total, bool enabled, double delay_s)
    : label_(std::move(label)), total_(total), enabled_(enabled), delay_s_(delay_s) {}

ProgressBar::~ProgressBar() {
  // Unwinding (an error, an interrupt): end the line where the bar stands rather than draw 100%.
  if (std::uncaught_exceptions() > 0 && !finished_.exchange(true)) {
    if (shown_.load()) std::fputc('\n', stderr);
    return;
  }
  finish();
}

void ProgressBar::tick(std::size_t n) {
  const std::size_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
  if (!enabled_ || finished_.load(std::memory_order_relaxed)) return;
  const auto ms = static_cast<std::int64_t>(watch_.elapsed_ms());
  if (static_cast<double>(ms) < delay_s_ * 1000.0) return;
  std::int64_t last = last_draw_ms_.load(std::memory_order_relaxed);
  if (ms - last < kRedrawIntervalMs) return;
  // Only the thread that claims this redraw slot draws; the others carry on working.
  if (!last_draw_ms_.compare_exchange_strong(last, ms)) return;
  shown_.store(true);
  draw(done);
}

void ProgressBar::finish() {
  if (finished_.exchange(true)) return;
  if (!shown_.load()) return;
  draw(total_);
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

void ProgressBar::draw(std::size_t done) {
  const double fraction = total_ == 0 ? 1.0 : std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const int filled = static_cast<int>(fraction * kBarWidth);
  std::string bar(kBarWidth, ' ');
  std::fill_n(bar.begin(), filled, '=');
  if (filled < kBarWidth) bar[filled] = '>';
  // One fprintf per redraw keeps the line whole when threads race.
  std::fprintf(stderr, "\r%s [%s] %3d%%", label_.c_str(), bar.c_str(), static_cast<int>(fraction * 100.0));
  std::fflush(stderr);
}

}  // namespace vf
