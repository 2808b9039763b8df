/*
 * Private helpers shared by the pdtfit sources: the real-type math mapping
 * and small checks. Not installed.
 */
#ifndef PDT_INTERNAL_H
#define PDT_INTERNAL_H

#include <math.h>

#include "pdt/pdt_common.h"

/* Literals and libm calls in the build's real type, so that the float build
 * never promotes to double (-Wdouble-promotion) and the double build never
 * truncates. */
#if PDT_REAL_DOUBLE
#define PDT_R(x)            (x)
#define pdt_sqrt            sqrt
#define pdt_exp             exp
#define pdt_log             log
#define pdt_sin             sin
#define pdt_cos             cos
#define pdt_sinh            sinh
#define pdt_cosh            cosh
#define pdt_atan            atan
#define pdt_atan2           atan2
#define pdt_fabs            fabs
#define pdt_floor           floor
#define pdt_pow             pow
#define pdt_hypot           hypot
#define PDT_REAL_EPS        2.220446049250313e-16
#define PDT_REAL_MAX        1.7976931348623157e308
#define PDT_REAL_MIN_NORMAL 2.2250738585072014e-308
#else
#define PDT_R(x)            (x##f)
#define pdt_sqrt            sqrtf
#define pdt_exp             expf
#define pdt_log             logf
#define pdt_sin             sinf
#define pdt_cos             cosf
#define pdt_sinh            sinhf
#define pdt_cosh            coshf
#define pdt_atan            atanf
#define pdt_atan2           atan2f
#define pdt_fabs            fabsf
#define pdt_floor           floorf
#define pdt_pow             powf
#define pdt_hypot           hypotf
#define PDT_REAL_EPS        1.1920929e-07f
#define PDT_REAL_MAX        3.4028235e+38f
#define PDT_REAL_MIN_NORMAL 1.17549435e-38f
#endif

#define PDT_PI PDT_R(3.14159265358979323846)

/* Constant tables of bytes that the library reads often and the caller
 * never sees (the identification's plan). On AVR, a Harvard core, const
 * data is copied into the 8 KiB of RAM at start-up unless it is placed in
 * flash and read with the program-memory load: PDT_ROM places a table
 * there, PDT_ROM_U8 reads one of its bytes. Elsewhere const data already
 * stays in flash, and both are plain. */
#if defined(__AVR__)
#include <avr/pgmspace.h>
#define PDT_ROM       PROGMEM
#define PDT_ROM_U8(p) ((uint8_t)pgm_read_byte(p))
#else
#define PDT_ROM
#define PDT_ROM_U8(p) (*(p))
#endif

/* expm1 and log1p in the real type: the C library's, or with
 * PDT_MATH_FALLBACK (pdt_config.h) the library's own (pdt_math.c). */
pdt_real_t pdt_math_expm1(pdt_real_t x);
pdt_real_t pdt_math_log1p(pdt_real_t x);
#if PDT_MATH_FALLBACK
#define pdt_expm1 pdt_math_expm1
#define pdt_log1p pdt_math_log1p
#elif PDT_REAL_DOUBLE
#define pdt_expm1 expm1
#define pdt_log1p log1p
#else
#define pdt_expm1 expm1f
#define pdt_log1p log1pf
#endif

static inline bool pdt_finite(pdt_real_t x)
{
    return isfinite(x) != 0;
}

#if PDT_VECTOR_LANES == 4
/* Four reals in the lanes of a host vector (the GCC and Clang vector
 * extension): the kernel's candidates, the sharing's pairs, the Fisher
 * pass's lags. Each lane's operations round as the scalar ones do, so a
 * lane's result is the scalar code's bit for bit. */
typedef pdt_real_t pdt_vec4_t __attribute__((vector_size(4 * sizeof(pdt_real_t))));

/* A macro, not a function: a vector return value would tie the ABI to
 * the vector width (GCC warns for 32-byte vectors without AVX). */
#define PDT_VEC4(x) ((pdt_vec4_t){(x), (x), (x), (x)})
#endif

/* A helper whose body is smaller than its call, called once a sample in
 * a loop (a bit of a mask, a sample of a recurrence): inlined even in a
 * build for size, where GCC otherwise keeps the call, a few bytes less
 * for several instructions more every sample. Not on the AVR, whose
 * floating point is a library call anyway (the call saved is one of
 * many) and whose flash the copies would fill (3.8 KB). */
#if defined(__GNUC__) && !defined(__AVR__)
#define PDT_INLINE_TINY static inline __attribute__((always_inline))
#else
#define PDT_INLINE_TINY static inline
#endif

/* Speed against size where a loop over a few parameters is hot (the
 * Fisher pass's samples, the sharing's pairs). With PDT_SPEED_OVER_SIZE a
 * caller may call a body from several sites with constant arguments;
 * PDT_FORCE_INLINE inlines it at each (as CMSIS's __STATIC_FORCEINLINE),
 * so that the constants shape its loops, and PDT_UNROLL unrolls the next
 * loop whole. GCC and Clang only, and not in a build for size (-Os, the
 * firmware's), which keeps one call site and one copy of each loop. */
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define PDT_SPEED_OVER_SIZE 1
#define PDT_FORCE_INLINE    static inline __attribute__((always_inline))
#define PDT_UNROLL          _Pragma("GCC unroll 8")
#else
#define PDT_SPEED_OVER_SIZE 0
#define PDT_FORCE_INLINE    static inline
#define PDT_UNROLL
#endif

/* The alignment pdt_real_t needs: its offset after a char. It is below
 * sizeof(pdt_real_t) on some targets (1 on AVR, where a float may lie at
 * any address, so a caller's uint8_t workspace is as good as any). */
typedef struct pdt_real_align {
    char c;
    pdt_real_t r;
} pdt_real_align_t;
#define PDT_REAL_ALIGN offsetof(pdt_real_align_t, r)

/* The first address of [base, base + room) aligned for any object
 * (sizeof(uintmax_t)) from which size bytes fit in the room; NULL where
 * they do not. Where a step-wise computation keeps its state in a
 * caller's workspace. */
static inline void *pdt_aligned_state(void *base, size_t room, size_t size)
{
    const uintptr_t a = (uintptr_t)sizeof(uintmax_t);
    const uintptr_t pad = (a - ((uintptr_t)base % a)) % a;
    if ((size_t)pad > room || size > room - (size_t)pad) {
        return NULL;
    }
    return (unsigned char *)base + pad;
}

/* True when p is aligned for pdt_real_t arrays. */
static inline bool pdt_aligned(const void *p)
{
    return ((uintptr_t)p % (uintptr_t)PDT_REAL_ALIGN) == 0u;
}

/* A delay_max resolved against the record length n (PDT_DELAY_HALF,
 * PDT_DELAY_QUARTER); other values pass through. */
static inline size_t pdt_delay_bound(size_t n, size_t delay_max)
{
    if (delay_max == PDT_DELAY_HALF) {
        return n / 2u;
    }
    if (delay_max == PDT_DELAY_QUARTER) {
        return n / 4u;
    }
    return delay_max;
}

/* The one way an object records that its init ran: init stores
 * PDT_MAGIC(...) of its module in the object's `magic` field, every later
 * call compares, and a zeroed or never-initialised object fails. */
#define PDT_MAGIC(a, b, c, d)                                                                      \
    (((uint32_t)(a) << 24) | ((uint32_t)(b) << 16) | ((uint32_t)(c) << 8) | (uint32_t)(d))

#endif /* PDT_INTERNAL_H */
