#pragma once
// Working storage kept per thread between uses (vectors that would otherwise grow afresh on every
// call, with their reallocations and page faults). A ThreadScratch<T> holds this thread's T while
// it lives; a second one alive on the same thread at the same time (a nested use) gets a T of its
// own instead, so two users never share one. The contents left by the last user stay: clear them.
namespace cdbench {

template <class T>
class ThreadScratch {
 public:
  ThreadScratch() : value_(claim()) {}
  ~ThreadScratch() {
    if (&value_ == &slot().value) slot().busy = false;
  }
  ThreadScratch(const ThreadScratch&) = delete;
  ThreadScratch& operator=(const ThreadScratch&) = delete;

  T& get() { return value_; }

 private:
  struct Slot {
    T value;
    bool busy = false;
  };
  static Slot& slot() {
    static thread_local Slot s;
    return s;
  }
  T& claim() {
    Slot& s = slot();
    if (s.busy) return own_;
    s.busy = true;
    return s.value;
  }

  T own_;  // used only when this thread's slot is taken (declared first: value_ may refer to it)
  T& value_;
};

}  // namespace cdbench
