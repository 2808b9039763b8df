/* pdtfit for Arduino: `#include <pdtfit.h>` gives the whole library
 * (pdt/pdt.h). Generated layout: tools/make_arduino_library.py. */
#ifndef PDTFIT_ARDUINO_H
#define PDTFIT_ARDUINO_H
#include "pdt/pdt.h"
#endif
