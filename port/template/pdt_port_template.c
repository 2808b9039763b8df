/*
 * Template for a new pdtfit port. Copy this file to port/<target>/, rename
 * it, and fill in each function for the target. Every function may stay as
 * it is here if the programs that need it are not run on the target: the
 * library itself does not call the port.
 */
#include "pdt_port.h"

void pdt_port_init(void)
{
    /* Start the clock and the console (e.g. the UART) here. */
}

void pdt_port_write(const char *text, size_t len)
{
    /* Send the bytes to the console; blocking is fine, only test and demo
     * programs write. */
    (void)text;
    (void)len;
}

uint64_t pdt_port_ticks(void)
{
    /* Return a free-running counter, e.g. DWT->CYCCNT widened to 64 bits. */
    return 0u;
}

uint64_t pdt_port_ticks_per_second(void)
{
    /* The counter's rate in Hz; 0 when there is no counter. */
    return 0u;
}

void pdt_port_assert_failed(const char *expr, const char *file, int line)
{
    /* Report (if there is a console) and stop for the debugger. */
    (void)expr;
    (void)file;
    (void)line;
    for (;;) {
    }
}

void pdt_port_exit(int status)
{
    /* Tell the test runner the status (semihosting SYS_EXIT, a GPIO, ...). */
    (void)status;
    for (;;) {
    }
}
