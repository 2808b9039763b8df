/* The few Arduino core declarations the example sketch uses, so that
 * tools/check_packages.py can compile it as the Arduino builder would
 * (sketch as C++, library sources as C) without an Arduino core. Not part
 * of the library. */
#ifndef PDTFIT_CI_ARDUINO_H
#define PDTFIT_CI_ARDUINO_H
#include <stddef.h>
#include <stdint.h>

#if defined(__AVR__)
/* On AVR the text goes out of USART0, which simavr prints: the AVR
 * example is run, not only linked (main.cpp). */
class CiSerial
{
  public:
    void begin(unsigned long baud);
    void print(const char *s);
    void println(const char *s);
    void println(double v);
};
#else
class CiSerial
{
  public:
    void begin(unsigned long baud)
    {
        (void)baud;
    }
    void print(const char *s)
    {
        (void)s;
    }
    void println(const char *s)
    {
        (void)s;
    }
    void println(double v)
    {
        (void)v;
    }
};
#endif
extern CiSerial Serial;
void delay(unsigned long ms);
void setup();
void loop();
#endif
