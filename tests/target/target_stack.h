/*
 * The stack measure of the port the target test program runs on
 * (target_util.c): the AVR's (port/avr-simavr), or that of every 32-bit
 * target port (port/pdt_port_target.h).
 */
#ifndef PDT_TARGET_STACK_H
#define PDT_TARGET_STACK_H

#if defined(__AVR__)
#include "pdt_port_avr.h"
#define t_port_stack_used  pdt_avr_stack_used
#define t_port_stack_paint pdt_avr_stack_paint
#else
#include "pdt_port_target.h"
#define t_port_stack_used  pdt_port_stack_used
#define t_port_stack_paint pdt_port_stack_paint
#endif

#endif /* PDT_TARGET_STACK_H */
