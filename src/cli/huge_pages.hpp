// Transparent huge pages for the command-line program's memory.
//
// Most of a large run's memory is written once, fresh: the density field, the FFT buffers and,
// on lavapipe, every device buffer (host memory from malloc), the mesh's host arrays. Each 4 KiB
// page costs a fault at first touch; on the 2-core VM of docs/performance.md that is about 7 us a
// page, 2 s of system time in 1AON's 9 s. glibc (2.35 and later) marks its heap and its mmap'd
// chunks for transparent huge pages when the tunable glibc.malloc.hugetlb=1 is set, one fault
// per 2 MiB, but reads tunables only when the process starts.
#pragma once

namespace fdmsurf::cli {

// Whether this build on this host would ask for huge pages: glibc 2.35 or later (the tunable),
// its allocator in use (no sanitizer's), and the kernel's THP mode "madvise" ("always" gives them
// without asking, "never" not at all).
bool huge_pages_on_request();

// When huge_pages_on_request(), GLIBC_TUNABLES does not mention it, FDMSURF_HUGE_PAGES is
// not "0", and neither valgrind nor a secure-mode (setuid) start is in the way:
// sets glibc.malloc.hugetlb=1 in GLIBC_TUNABLES (and FDMSURF_HUGE_PAGES_RESTARTED=1, so that the
// restarted program never restarts again) and restarts the program in place (execv of
// /proc/self/exe with the same arguments, argv[0] included). Returns when it does not restart,
// also when the restart fails (the environment put back; the run goes on with small pages).
// Call first thing in main.
void restart_with_huge_pages(char** argv);

}  // namespace fdmsurf::cli
