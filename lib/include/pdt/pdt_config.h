/*
 * pdtfit build configuration.
 *
 * Every setting has a default here. To change one, either define it on the
 * compiler command line (CMake does this for PDT_REAL_DOUBLE) or define
 * PDT_USER_CONFIG_FILE as the name of a header of your own, e.g.
 * -DPDT_USER_CONFIG_FILE='"my_pdt_config.h"', that sets the values you want.
 * This file is the only place the defaults live; CMake options mirror it.
 */
#ifndef PDT_CONFIG_H
#define PDT_CONFIG_H

/* SIZE_MAX: the limits below follow the width of size_t (16 bits on AVR
 * and MSP430, where int is 16 bits too). A tool that reads no system
 * header (a static analyser) sees no SIZE_MAX and gets the defaults of a
 * 32-bit size_t. */
#include <stdint.h>

#ifdef PDT_USER_CONFIG_FILE
#include PDT_USER_CONFIG_FILE
#endif

/* 0: pdt_real_t is float (the default: single-precision FPUs such as the
 * Cortex-M4F run it in hardware). 1: pdt_real_t is double. */
#ifndef PDT_REAL_DOUBLE
#define PDT_REAL_DOUBLE 0
#endif
#if (PDT_REAL_DOUBLE != 0) && (PDT_REAL_DOUBLE != 1)
#error "PDT_REAL_DOUBLE must be 0 (float) or 1 (double)"
#endif
/* avr-gcc's double is float (32 bits) unless -mdouble=64 is given: a
 * double build there would be a float build under another name. */
#if PDT_REAL_DOUBLE && defined(__AVR__) && (!defined(__SIZEOF_DOUBLE__) || __SIZEOF_DOUBLE__ < 8)
#error "PDT_REAL_DOUBLE needs a 64-bit double; avr-gcc's double is 32 bits: use the float build"
#endif

/* Largest real FFT the library accepts, as log2 of the size. The FFT code
 * has no tables of its own, so this bounds only the sizes callers may ask
 * for (and therefore the record length the cost accepts). Default 16, or
 * 10 where size_t has 16 bits. Every workspace derived from an FFT size
 * N_f is below 32 N_f bytes (at most 3.5 N_f reals of 8 bytes, plus the
 * population's few hundred), so 32 * 2^PDT_FFT_MAX_LOG2 must fit size_t. */
#ifndef PDT_FFT_MAX_LOG2
#if !defined(SIZE_MAX) || (SIZE_MAX > 0xFFFFu)
#define PDT_FFT_MAX_LOG2 16
#else
#define PDT_FFT_MAX_LOG2 10
#endif
#endif
#if (PDT_FFT_MAX_LOG2 < 4) || (PDT_FFT_MAX_LOG2 > 24)
#error "PDT_FFT_MAX_LOG2 must be between 4 and 24"
#endif
#if defined(SIZE_MAX) && ((SIZE_MAX >> (PDT_FFT_MAX_LOG2 + 5)) == 0)
#error "PDT_FFT_MAX_LOG2 too large for this size_t: 32 * 2^PDT_FFT_MAX_LOG2 bytes must fit"
#endif

/* Fewest samples a cost may be computed from (after the delay bound has
 * removed the start of the record). Fewer than this cannot tell a model
 * from noise, so such records are refused with PDT_ERR_TOO_SHORT. */
#ifndef PDT_MIN_SAMPLES
#define PDT_MIN_SAMPLES 16
#endif
#if PDT_MIN_SAMPLES < 4
#error "PDT_MIN_SAMPLES must be at least 4"
#endif

/* Most lags pdt_reduce_half_rule accepts: it sorts a copy of them on the
 * stack (PDT_REDUCE_MAX_LAGS reals and flags, per lag). */
#ifndef PDT_REDUCE_MAX_LAGS
#define PDT_REDUCE_MAX_LAGS 32u
#endif
#if (PDT_REDUCE_MAX_LAGS < 1) || (PDT_REDUCE_MAX_LAGS > 1024)
#error "PDT_REDUCE_MAX_LAGS must be between 1 and 1024"
#endif

/* Most frequencies pdt_reduce_sung fits (pdt_reduce_config_t.n_freq): its
 * work grows with n_freq times the plant's order, so the bound keeps one
 * call's work bounded. Larger n_freq is refused with PDT_ERR_LENGTH. */
#ifndef PDT_REDUCE_MAX_FREQ
#define PDT_REDUCE_MAX_FREQ 4096u
#endif
#if (PDT_REDUCE_MAX_FREQ < 2) || (PDT_REDUCE_MAX_FREQ > 1048576)
#error "PDT_REDUCE_MAX_FREQ must be between 2 and 1048576"
#endif

/* Most samples a record may hold: the capacity of pdt_record_init and of
 * pdt_autotune_config_t. One autotune scan evaluates the cost over the
 * whole record, so this bounds a scan's work (and keeps every byte count
 * derived from a capacity far from overflowing size_t: those are below
 * 32 bytes a sample). Default 2^20, or 1024 where size_t has 16 bits.
 * Larger capacities are refused with PDT_ERR_LENGTH. */
#ifndef PDT_MAX_SAMPLES
#if !defined(SIZE_MAX) || (SIZE_MAX > 0xFFFFu)
#define PDT_MAX_SAMPLES 1048576u
#else
#define PDT_MAX_SAMPLES 1024u
#endif
#endif
#if (PDT_MAX_SAMPLES < 64) || (PDT_MAX_SAMPLES > 134217728)
#error "PDT_MAX_SAMPLES must be between 64 and 2^27"
#endif
#if defined(SIZE_MAX) && ((PDT_MAX_SAMPLES - 1) > (SIZE_MAX >> 5))
#error "PDT_MAX_SAMPLES too large for this size_t: 32 bytes a sample must fit"
#endif

/* Most records one identification fits together (pdt_ident.h: the first
 * and pdt_ident_config_t.more), 1 .. 8. Default 8, or 1 where size_t has
 * 16 bits (AVR, MSP430: RAM for one record), which leaves the joint fit
 * of several records (pdt_cost_joint_profile) out of the link: about
 * 4 KiB of an AVR's flash. With 1, a further record is refused
 * (PDT_ERR_ARG). */
#ifndef PDT_IDENT_MAX_RECORDS
#if !defined(SIZE_MAX) || (SIZE_MAX > 0xFFFFu)
#define PDT_IDENT_MAX_RECORDS 8u
#else
#define PDT_IDENT_MAX_RECORDS 1u
#endif
#endif
#if (PDT_IDENT_MAX_RECORDS < 1) || (PDT_IDENT_MAX_RECORDS > 8)
#error "PDT_IDENT_MAX_RECORDS must be between 1 and 8"
#endif

/* Candidates the identification evaluates in one pass over the record, a
 * vector lane each: 4 where GCC or Clang offers SSE2 or NEON, else 1 (a
 * Cortex-M has no lanes to use). Define as 1 to leave the vector kernel
 * out; with 4, one call of pdt_ident_step may evaluate a whole group when
 * asked for fewer (docs/ident-engine.md). */
#ifndef PDT_VECTOR_LANES
#if defined(__GNUC__) && (defined(__SSE2__) || defined(__ARM_NEON))
#define PDT_VECTOR_LANES 4
#else
#define PDT_VECTOR_LANES 1
#endif
#endif
#if (PDT_VECTOR_LANES != 1) && (PDT_VECTOR_LANES != 4)
#error "PDT_VECTOR_LANES must be 1 or 4"
#endif

/* 1: expm1 and log1p come from the library's own fallbacks
 * (lib/src/pdt_math.c: exp and log with Kahan's corrections, within a few
 * ulps), for a C library that lacks them. 0: from <math.h> (expm1f and
 * log1pf in the float build). Default 1 with avr-libc, which has neither,
 * else 0. */
#ifndef PDT_MATH_FALLBACK
#if defined(__AVR__)
#define PDT_MATH_FALLBACK 1
#else
#define PDT_MATH_FALLBACK 0
#endif
#endif
#if (PDT_MATH_FALLBACK != 0) && (PDT_MATH_FALLBACK != 1)
#error "PDT_MATH_FALLBACK must be 0 or 1"
#endif

/* Checks of programmer errors that cost time on every call. By default they
 * compile to nothing; define PDT_ASSERT(x) to your handler to enable them,
 * for example to the port's handler (port/pdt_port.h), in a user config
 * header:
 *   void pdt_port_assert_failed(const char *expr, const char *file, int line);
 *   #define PDT_ASSERT(x) ((x) ? (void)0 : pdt_port_assert_failed(#x, __FILE__, __LINE__))
 * Argument checks that return a status are always on and do not use this. */
#ifndef PDT_ASSERT
#define PDT_ASSERT(x) ((void)0)
#endif

#endif /* PDT_CONFIG_H */
