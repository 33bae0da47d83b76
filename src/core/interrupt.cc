#include "core/interrupt.h"

#include <atomic>
#include <csignal>

namespace motionfork {
namespace {

std::atomic<bool> g_requested{false};
using Handler = void (*)(int);
Handler g_previous = SIG_DFL;

extern "C" void OnSigint(int) { g_requested = true; }

}  // namespace

InterruptRequest::InterruptRequest() {
  g_requested = false;
  g_previous = std::signal(SIGINT, OnSigint);
}

InterruptRequest::~InterruptRequest() { std::signal(SIGINT, g_previous); }

bool InterruptRequest::requested() { return g_requested.load(); }

}  // namespace motionfork
