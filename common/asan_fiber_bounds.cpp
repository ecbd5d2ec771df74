// Linked into every executable of the AddressSanitizer build (RTSIM_SANITIZE, top-level
// CMakeLists.txt), into no library and no installed file.
//
// Debian's SystemC tells ASan of each coroutine switch (__sanitizer_start/finish_switch_fiber in
// sc_cor_qt), but a thread process that ends leaves the main thread's recorded stack at that
// coroutine's stack, which SystemC frees later. At exit LeakSanitizer then scans that range for
// pointers: its stack pointer is outside it, so it scans all of it, and a page unmapped since
// kills its tracer ("Tracer caught signal 11", about one run in four of a short test here; a
// test failed twice in a row fails CI). Before the leak check this puts the main stack back when
// exit runs on it. Exit on a coroutine's stack keeps that coroutine's range, which is right.
#if defined(__SANITIZE_ADDRESS__)
#include <pthread.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

extern "C" void __sanitizer_start_switch_fiber(void** fake_stack_save, const void* bottom,
                                               std::size_t size);
extern "C" void __sanitizer_finish_switch_fiber(void* fake_stack_save, const void** bottom_old,
                                                std::size_t* size_old);

namespace {

void restore_main_stack_bounds() {
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) != 0) return;
  void* bottom = nullptr;
  std::size_t size = 0;
  const bool known = pthread_attr_getstack(&attr, &bottom, &size) == 0;
  pthread_attr_destroy(&attr);
  const char here = 0;
  const auto sp = reinterpret_cast<std::uintptr_t>(&here);
  const auto begin = reinterpret_cast<std::uintptr_t>(bottom);
  if (!known || sp < begin || sp >= begin + size) return;
  __sanitizer_start_switch_fiber(nullptr, bottom, size);
  __sanitizer_finish_switch_fiber(nullptr, nullptr, nullptr);
}

// Registered after the sanitizer's own exit handler, so run before it (atexit is last in, first
// out).
[[maybe_unused]] const int registered = std::atexit(restore_main_stack_bounds);

}  // namespace
#endif
