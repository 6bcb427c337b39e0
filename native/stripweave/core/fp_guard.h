// Floating-point traps inside native calls (issue 23): no native failure may
// kill the process (a FreeCAD macro would take the user's unsaved work down).
//
// FloatingPointGuard (RAII, per thread), held by every binding that runs the
// core (native/python/bind.h: NativeCall) and by parallel_for's workers when
// their caller holds one. While it lives, on its thread:
//   - every floating-point exception is masked (feholdexcept): no arithmetic
//     traps, even where the host (FreeCAD, OCCT's OSD::SetSignal, a macro)
//     enabled traps; the caller's environment (flags and masks) comes back
//     when the guard ends;
//   - a SIGFPE that a call raises (GMP raises one deliberately on a division
//     by zero and aborts if the handler returns; anchors near 1e307 did this
//     inside CGAL's closest-point search) becomes an InputError, thrown from
//     the signal handler, so the frames in between unwind as for any throw.
//
// Why throwing from the handler is sound here (and siglongjmp is not):
//   - only a signal sent by a call is turned into an exception (si_code <= 0:
//     raise, kill, tgkill). The interrupted instruction is then a call to
//     raise(), a normal call site, and the x86-64 unwinder steps through the
//     signal frame (glibc's __restore_rt carries unwind info for this). Every
//     C++ frame between it and the binding runs its destructors (memory
//     freed, locks released, parallel_for's threads joined), which a
//     siglongjmp past them would skip; GMP checks a zero divisor before it
//     allocates or writes anything, so it leaves nothing half done either;
//   - the handler is installed with SA_NODEFER: leaving it by a throw skips
//     sigreturn, and the signal must not stay blocked on the thread;
//   - a trap from an instruction (si_code > 0: an integer division by zero,
//     or a floating-point trap outside a guard) cannot be unwound reliably
//     (the faulting instruction is no call site), so it goes to the handler
//     that was there before ours (the default one ends the process, as it
//     did before). Inside a guard floating-point arithmetic cannot trap, and
//     integer division by zero is a bug the sanitizer fuzzing looks for.
// Outside every guard the handler passes any SIGFPE on to the previous
// handler (Python's faulthandler, FreeCAD's, or the default), unchanged.
//
// raise_fp_trap_for_test(kind): a test entry, run inside a guard by the
// bindings: "gmp" divides by zero in GMP (SIGFPE from GMP itself),
// "gmp-worker" the same in parallel_for's worker threads, "raise" raises
// SIGFPE, "float" enables the divide-by-zero trap as a host might, divides
// 1 by 0 in a nested guard (no trap: inf) and restores the host's setting.
#pragma once

#include <cfenv>
#include <string>

namespace stripweave {

class FloatingPointGuard {
 public:
  FloatingPointGuard();
  ~FloatingPointGuard();
  FloatingPointGuard(const FloatingPointGuard&) = delete;
  FloatingPointGuard& operator=(const FloatingPointGuard&) = delete;
  // Whether the calling thread holds a guard (parallel_for's workers take one then).
  static bool active();

 private:
  std::fenv_t saved_;
};

void raise_fp_trap_for_test(const std::string& kind);

}  // namespace stripweave
