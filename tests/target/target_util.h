/*
 * Helpers of the target test program: a line of text built without stdio
 * (newlib's printf would pull in its allocator and system calls) and the
 * verdict of one check. The measures are the host tests' own
 * (tests/support/test_measure.h).
 */
#ifndef PDT_TARGET_UTIL_H
#define PDT_TARGET_UTIL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pdt/pdt.h"
#include "test_measure.h"

/* One line of output, truncated (not overflowed) past its buffer. */
typedef struct tline {
    char buf[200];
    size_t n;
} tline_t;

void tl_init(tline_t *l);
void tl_str(tline_t *l, const char *s);
void tl_uint(tline_t *l, uint64_t v);
void tl_int(tline_t *l, int64_t v);
/* v with `digits` significant digits, fixed or with an exponent as %g. */
void tl_num(tline_t *l, double v, int digits);
/* A model's parameters, 5 digits each: "K .. tau .. Td .." of a FOPDT,
 * "K .. T1 .. T2 .. Td .." of a SOPDT by its time constants. */
void tl_fopdt(tline_t *l, const pdt_model_fopdt_t *m);
void tl_tc(tline_t *l, const pdt_model_tc_t *tc);
/* Writes the line and a newline to the console. */
void tl_emit(tline_t *l);

/* Prints "PASS <detail>" or "FAIL <detail>" and counts the verdict.
 * Returns 0 when ok, 1 otherwise, so checks can add up their failures. */
int t_verdict(bool ok, tline_t *detail);

/* Prints an informational line, "info <detail>". */
void t_info(tline_t *detail);

/* Ticks of the port counter converted to instructions: with QEMU's
 * -icount shift=0, one instruction is one nanosecond of the emulated clock,
 * so a counter of f Hz advances once per 1e9 / f of them (40 at the M4F's
 * 25 MHz, 1 for the RISC-V port's instruction count). */
uint64_t t_ticks_to_instructions(uint64_t ticks);

/* Repaints the free stack (pdt_port_stack_paint) to measure one call,
 * keeping the program's high-water mark so far for t_stack_max. */
void t_stack_repaint(void);

/* The deepest stack use of the whole run, bytes. */
size_t t_stack_max(void);

/* Checks run and failed so far (all t_verdict calls). */
unsigned t_checks_run(void);
unsigned t_checks_failed(void);

#endif /* PDT_TARGET_UTIL_H */
