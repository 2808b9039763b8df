/*
 * pdtfit: first- and second-order-plus-dead-time model identification for
 * controllers, in fixed memory. Umbrella header: include this, or only the
 * module headers you use.
 */
#ifndef PDT_H
#define PDT_H

#include "pdt/pdt_autotune.h"
#include "pdt/pdt_common.h"
#include "pdt/pdt_cost.h"
#include "pdt/pdt_discrete.h"
#include "pdt/pdt_excite.h"
#include "pdt/pdt_fft.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_ls.h"
#include "pdt/pdt_model.h"
#include "pdt/pdt_monitor.h"
#include "pdt/pdt_pid.h"
#include "pdt/pdt_record.h"
#include "pdt/pdt_reduce.h"
#include "pdt/pdt_status.h"
#include "pdt/pdt_tune.h"
#include "pdt/pdt_validate.h"

#endif /* PDT_H */
