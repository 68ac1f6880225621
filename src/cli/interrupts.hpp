// SIGINT, SIGTERM and SIGHUP in the CLI: the run stops at once, every temporary output file
// being written is removed (no output is renamed into place before it is complete, so none is
// partial), one line says so on stderr, and the exit status is 128 + the signal's number
// (130 for Ctrl-C, 143 for SIGTERM), as shells report a process killed by it.
#pragma once

namespace fdmsurf::cli {

// Installs the handlers (once, from main()).
void install_interrupt_handlers();

}  // namespace fdmsurf::cli
