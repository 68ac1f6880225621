// Interrupt handlers of the CLI (interrupts.hpp). Only async-signal-safe calls in the handler:
// unlink (through the temporary-file table), write and _exit.
#include "cli/interrupts.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>

#include "base/temp_files.hpp"

namespace fdmsurf::cli {

namespace {

void write_stderr(const char* text) {
    std::size_t left = std::strlen(text);
    while (left > 0) {
        const ssize_t n = ::write(STDERR_FILENO, text, left);
        if (n <= 0) return;
        text += n;
        left -= std::size_t(n);
    }
}

extern "C" void on_interrupt(int sig) {
    detail::remove_temp_files_from_signal_handler();
    const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
    // \r and an erased line: a progress line, when there is one, does not run into the message.
    write_stderr(isatty(STDERR_FILENO) ? "\r\033[K" : "");
    write_stderr("fdmsurf: error: interrupted by ");
    write_stderr(name);
    write_stderr("; stopped, the output being written was removed (finished outputs are complete)\n");
    ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handlers() {
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, sig);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &action, nullptr);
}

}  // namespace fdmsurf::cli
