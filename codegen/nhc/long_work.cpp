#include "nhc/long_work.hpp"

#include <atomic>
#include <chrono>

namespace nhc {

namespace {

using Clock = std::chrono::steady_clock;

thread_local LongWorkObserver* current = nullptr;
thread_local Clock::time_point last_check{};
std::atomic<SymbolicLock*> symbolic_lock{nullptr};

}  // namespace

ObservedWork::ObservedWork(LongWorkObserver& observer) : previous_(current) {
  current = &observer;
  last_check = Clock::now();
}

ObservedWork::~ObservedWork() { current = previous_; }

LongWorkObserver* current_observer() { return current; }

void check_for_stop_now() {
  if (current == nullptr) return;
  last_check = Clock::now();
  if (current->stop_requested()) throw WorkInterrupted();
}

void check_for_stop() {
  if (current == nullptr) return;
  if (Clock::now() - last_check < std::chrono::milliseconds(kStopCheckMilliseconds)) return;
  check_for_stop_now();
}

void set_symbolic_lock(SymbolicLock* lock) { symbolic_lock = lock; }

SymbolicSection::SymbolicSection() : lock_(symbolic_lock) {
  if (lock_ != nullptr) lock_->lock();
}

SymbolicSection::~SymbolicSection() {
  if (lock_ != nullptr) lock_->unlock();
}

WaitingForProcess::WaitingForProcess() : observer_(current) {
  if (observer_ != nullptr) observer_->waiting_begins();
}

WaitingForProcess::~WaitingForProcess() {
  if (observer_ != nullptr) observer_->waiting_ends();
}

}  // namespace nhc
