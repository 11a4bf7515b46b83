// SPDX-License-Identifier: MIT
#include "vsculpt/app/Interrupt.h"

#include "vsculpt/core/WriteFileAtomically.h"

#include <signal.h>

#include <atomic>
#include <cassert>

namespace vsculpt::app {

namespace {

// Lock-free atomics only: the handler reads and writes them.
std::atomic<bool> sInScope{false};
std::atomic<int> sNoted{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

const int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

// Removes the temporary files of writes in progress and raises `sig` with its default
// action: the process ends as the signal says (from a handler, once the handler returns, as
// the signal is blocked while it runs). Async-signal-safe: unlink, sigaction, raise.
void endBy(int sig) {
    core::removeTemporaryFilesInProgress();
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(sig, &dfl, nullptr);
    ::raise(sig);
}

extern "C" void onInterrupt(int sig) {
    int none = 0;
    if (sInScope.load() && sNoted.compare_exchange_strong(none, sig)) return;
    endBy(sig);
}

}  // namespace

void handleInterrupts() {
    for (int sig : kSignals) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) != 0) continue;
        // Ignored (nohup, a parent's choice) stays ignored; a handler someone else set stays.
        if (old.sa_handler != SIG_DFL) continue;
        struct sigaction sa {};
        sa.sa_handler = onInterrupt;
        sigemptyset(&sa.sa_mask);
        ::sigaction(sig, &sa, nullptr);
    }
}

InterruptScope::InterruptScope() {
    handleInterrupts();
    [[maybe_unused]] const bool was = sInScope.exchange(true);
    assert(!was && "one InterruptScope at a time");
}

InterruptScope::~InterruptScope() {
    sInScope.store(false);
}

int interruptSignal() {
    return sNoted.load();
}

int takeInterruptSignal() {
    return sNoted.exchange(0);
}

void endIfInterrupted() {
    if (const int sig = sNoted.exchange(0)) endBy(sig);
}

}  // namespace vsculpt::app
