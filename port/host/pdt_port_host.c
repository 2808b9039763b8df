/* Host (POSIX) port: stdout, CLOCK_MONOTONIC, exit(). */
#define _POSIX_C_SOURCE 199309L

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "pdt_port.h"

void pdt_port_init(void)
{
}

void pdt_port_write(const char *text, size_t len)
{
    (void)fwrite(text, 1, len, stdout);
}

uint64_t pdt_port_ticks(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) {
        return 0u;
    }
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

uint64_t pdt_port_ticks_per_second(void)
{
    return 1000000000u;
}

void pdt_port_assert_failed(const char *expr, const char *file, int line)
{
    (void)fflush(stdout);
    (void)fprintf(stderr, "%s:%d: PDT_ASSERT(%s) failed\n", file, line, expr);
    abort();
}

void pdt_port_exit(int status)
{
    (void)fflush(stdout);
    exit(status);
}
