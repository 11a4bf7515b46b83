// SPDX-License-Identifier: MIT
/// @file Interrupt.h
/// @brief What SIGINT (Ctrl-C), SIGTERM and SIGHUP do: end the process without leaving
/// half-written files, or, while a window or a recording runs, first ask it to finish its work
/// as its own close would.
#pragma once

namespace vsculpt::app {

/// For main(), once: SIGINT, SIGTERM and SIGHUP (where not ignored) remove the temporary files
/// of writes in progress (core::removeTemporaryFilesInProgress), then end the process as they
/// would have: Ctrl-C during an export leaves neither the export nor a hidden temporary file.
/// Inside an InterruptScope the first of them only asks the loop to stop (see there).
void handleInterrupts();

/// While one lives, the first SIGINT, SIGTERM or SIGHUP is only noted (interruptSignal()):
/// the window or recording checks it once a frame and closes as its close box would, ending
/// the stroke in flight and snapshotting the project, so the next open has nothing to
/// recover. A second signal ends the process at once, as outside a scope. Installs the
/// handlers itself if main() has not. Not nestable; one at a time per process.
class InterruptScope {
  public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

/// The signal an InterruptScope noted and not yet taken, 0 if none.
int interruptSignal();

/// Returns interruptSignal() and forgets it: for a loop whose documented way to stop is
/// Ctrl-C (`vsculpt record`), which then ends normally.
int takeInterruptSignal();

/// For main(), after the command returned: if a signal was noted and not taken, ends the
/// process as that signal says (130 for SIGINT, 143 for SIGTERM in a shell), after removing
/// any temporary file still there; otherwise returns.
void endIfInterrupted();

}  // namespace vsculpt::app
