#include "nhc/expr/work_stage.hpp"

#include <time.h>

#include <atomic>
#include <mutex>

#include "nhc/base/number_text.hpp"

namespace nhc::work_budget {

namespace {

double process_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Written by the working thread, read by the watchdog: atomics, no locks on the hot path.
std::atomic<const char*> current_stage{nullptr};
std::atomic<double> spent_before{0};  // seconds inside stages before the current outermost one
std::atomic<double> entered_at{0};    // process time when the current outermost stage began
std::mutex scene_mutex;
std::string scene;  // kept alive for the snapshot's pointer: set before the stages run

}  // namespace

Stage::Stage(const char* name) : outer_(current_stage.load()) {
  if (outer_ == nullptr) entered_at.store(process_seconds());
  current_stage.store(name);
}

Stage::~Stage() {
  if (outer_ == nullptr) spent_before.store(spent_before.load() + process_seconds() - entered_at.load());
  current_stage.store(outer_);
}

void set_scene_path(const std::string& path) {
  std::lock_guard<std::mutex> lock(scene_mutex);
  scene = path;
}

StageSnapshot stage_snapshot() {
  StageSnapshot s;
  s.stage = current_stage.load();
  s.seconds = spent_before.load() + (s.stage != nullptr ? process_seconds() - entered_at.load() : 0.0);
  std::lock_guard<std::mutex> lock(scene_mutex);
  s.scene_path = scene.c_str();
  return s;
}

ProcessorTimeLimit::ProcessorTimeLimit(double seconds) : seconds_(seconds), start_(stage_snapshot().seconds) {}

bool ProcessorTimeLimit::exceeded() {
  if (exceeded_) return true;
  const StageSnapshot s = stage_snapshot();
  if (s.stage == nullptr || s.seconds - start_ <= seconds_) return false;
  exceeded_ = true;
  stage_ = s.stage;
  scene_ = s.scene_path;
  return true;
}

std::string ProcessorTimeLimit::message(const std::string& how_to_raise) const {
  return stage_ + " took more than " + base::number_text(seconds_, 3) +
         " s of processor time: the expressions grow too large (" + how_to_raise + ")";
}

}  // namespace nhc::work_budget
