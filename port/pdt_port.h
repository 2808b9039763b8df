/*
 * The pdtfit port surface: the few things pdtfit's own programs (tests,
 * demo, benchmarks, target test runners) need from a platform.
 *
 * lib/ never calls these, with one opt-in exception: a build that maps
 * PDT_ASSERT to pdt_port_assert_failed (pdt_config.h shows how). A firmware that
 * only links the library needs no port at all.
 *
 * To support a new target, copy template/pdt_port_template.c into a folder
 * named after the target and fill in the functions.
 */
#ifndef PDT_PORT_H
#define PDT_PORT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Brings up whatever the other calls need (clock, UART). Idempotent. */
void pdt_port_init(void);

/* Writes len bytes of text to the console (UART, semihosting, stdout). */
void pdt_port_write(const char *text, size_t len);

/* A monotonic counter and its rate, for benchmarks. A target without a
 * timer returns 0 from both; callers then report no timing. */
uint64_t pdt_port_ticks(void);
uint64_t pdt_port_ticks_per_second(void);

/* Called by PDT_ASSERT when enabled; reports and stops. Does not return. */
void pdt_port_assert_failed(const char *expr, const char *file, int line);

/* Ends the program with a status a test runner can read (exit code,
 * semihosting exit). Does not return. */
void pdt_port_exit(int status);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PORT_H */
