// See fp_guard.h (why throwing from this signal handler is sound is argued there).
#include "stripweave/core/fp_guard.h"

#include "stripweave/core/error.h"
#include "stripweave/core/parallel.h"

#include <gmp.h>

#include <csignal>
#include <mutex>

namespace stripweave {

namespace {

thread_local int t_depth = 0;         // guards alive on this thread
thread_local bool t_chaining = false;  // inside the previous handler: never re-enter it
struct sigaction g_previous;           // the SIGFPE handler ours replaced
std::mutex g_install_mutex;

void on_sigfpe(int sig, siginfo_t* info, void* context);

void pass_on(int sig, siginfo_t* info, void* context) {
  const auto handler = g_previous.sa_handler;
  if (t_chaining || handler == SIG_DFL) {
    // The default action, as without us: end the process with SIGFPE.
    signal(SIGFPE, SIG_DFL);
    raise(SIGFPE);
    return;  // an instruction's trap: returning re-executes it under the default action
  }
  if (handler == SIG_IGN) return;
  t_chaining = true;
  if (g_previous.sa_flags & SA_SIGINFO)
    g_previous.sa_sigaction(sig, info, context);
  else
    handler(sig);
  t_chaining = false;
}

void on_sigfpe(int sig, siginfo_t* info, void* context) {
  const bool sent_by_a_call = info == nullptr || info->si_code <= 0;  // SI_USER, SI_TKILL, SI_QUEUE
  if (t_depth > 0 && sent_by_a_call)
    throw InputError(
        "a floating-point trap (SIGFPE, e.g. a division by zero in exact arithmetic) stopped the computation: "
        "the input holds degenerate or out-of-range numbers");
  pass_on(sig, info, context);
}

// Ours stays installed: when someone replaced it since (FreeCAD, OCCT), it
// goes back in front and passes what it does not handle on to theirs.
void install_handler() {
  std::lock_guard<std::mutex> lock(g_install_mutex);
  struct sigaction current;
  if (sigaction(SIGFPE, nullptr, &current) != 0) return;
  const bool ours = (current.sa_flags & SA_SIGINFO) && current.sa_sigaction == on_sigfpe;
  if (ours) return;
  struct sigaction mine = {};
  mine.sa_sigaction = on_sigfpe;
  mine.sa_flags = SA_SIGINFO | SA_NODEFER;  // left by a throw: the signal must not stay blocked
  sigemptyset(&mine.sa_mask);
  g_previous = current;
  sigaction(SIGFPE, &mine, nullptr);
}

}  // namespace

FloatingPointGuard::FloatingPointGuard() {
  install_handler();
  feholdexcept(&saved_);  // saves the caller's environment, clears the flags, masks every trap
  ++t_depth;
}

FloatingPointGuard::~FloatingPointGuard() {
  --t_depth;
  fesetenv(&saved_);
}

bool FloatingPointGuard::active() { return t_depth > 0; }

void raise_fp_trap_for_test(const std::string& kind) {
  if (kind == "gmp" || kind == "gmp-worker") {
    auto divide_by_zero = [](Index) {
      mpz_t n, zero, q;
      mpz_init_set_ui(n, 7);
      mpz_init(zero);
      mpz_init(q);
      mpz_tdiv_q(q, n, zero);  // GMP: raise(SIGFPE), then abort() if that returns
      mpz_clears(n, zero, q, nullptr);
    };
    if (kind == "gmp") divide_by_zero(0);
    else parallel_for(64, divide_by_zero, 2);
  } else if (kind == "raise") {
    raise(SIGFPE);
  } else if (kind == "float") {
    std::fenv_t host;
    fegetenv(&host);
    feenableexcept(FE_DIVBYZERO | FE_INVALID | FE_OVERFLOW);  // what a host may have done
    double result;
    {
      FloatingPointGuard guard;
      volatile double zero = 0.0;
      result = 1.0 / zero;  // masked: inf, no trap
    }
    fesetenv(&host);
    if (result != result + 1.0 || result <= 0) throw InputError("1/0 did not give +inf");
  } else {
    throw InputError("unknown floating-point trap test '" + kind + "' (gmp, gmp-worker, raise, float)");
  }
}

}  // namespace stripweave
