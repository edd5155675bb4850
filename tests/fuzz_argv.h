/* fuzz_argv.h — the run-time side of the argv fuzz target
 * (fuzz_argv_rt.c): calling a tool's main as a function and getting back
 * what a process exit would have cleaned up. */
#ifndef FUZZ_ARGV_H
#define FUZZ_ARGV_H

/* Once, before the first call: where the tools' output goes. */
void fuzz_argv_rt_init(void);
/* Calls main(argc, argv) with exit() coming back here; then runs the atexit
 * handlers the tool registered, closes the descriptors, streams, files,
 * model runs, sources and renderers it left open, unlists its temporaries
 * and restores the signal dispositions. The exit status. */
int fuzz_argv_call(int (*main_fn)(int, char **), int argc, char **argv);

#endif
