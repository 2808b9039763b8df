#include "pdt/pdt_status.h"

const char *pdt_status_str(pdt_status_t status)
{
    switch (status) {
    case PDT_RUNNING:
        return "running";
    case PDT_OK:
        return "ok";
    case PDT_ERR_ARG:
        return "bad argument";
    case PDT_ERR_LENGTH:
        return "unsupported length";
    case PDT_ERR_NOMEM:
        return "workspace missing or too small";
    case PDT_ERR_NONFINITE:
        return "data not finite (NaN or infinity)";
    case PDT_ERR_TOO_SHORT:
        return "too few samples";
    case PDT_ERR_BOUNDS:
        return "lower bound above upper bound";
    case PDT_ERR_NO_FORM:
        return "model has no such form";
    case PDT_ERR_NO_EXCITATION:
        return "data do not excite the process";
    case PDT_ERR_STATE:
        return "call out of order";
    case PDT_ERR_PV_LIMIT:
        return "process value left its limits";
    case PDT_ERR_OUTPUT_LIMIT:
        return "output would leave its limits";
    case PDT_ERR_TIMEOUT:
        return "time limit passed";
    case PDT_ERR_SETPOINT:
        return "set-point on the wrong side";
    case PDT_ERR_POOR_FIT:
        return "model fits too poorly";
    case PDT_ERR_UNSTABLE:
        return "no stable loop for this model";
    case PDT_ERR_ABORTED:
        return "stopped by the caller";
    case PDT_ERR_NOT_AT_REST:
        return "record does not end at rest";
    case PDT_ERR_OUTLIER:
        return "gross outlier in the data";
    case PDT_ERR_MODEL_INVALID:
        return "data contradict the model";
    case PDT_ERR_UNCERTAIN:
        return "model too uncertain for robust gains";
    case PDT_ERR_DISTURBED:
        return "experiment disturbed";
    case PDT_ERR_MS_LIMIT:
        return "gains exceed the robustness limit Ms";
    default:
        return "unknown status";
    }
}

const char *pdt_status_name(pdt_status_t status)
{
    switch (status) {
    case PDT_RUNNING:
        return "PDT_RUNNING";
    case PDT_OK:
        return "PDT_OK";
    case PDT_ERR_ARG:
        return "PDT_ERR_ARG";
    case PDT_ERR_LENGTH:
        return "PDT_ERR_LENGTH";
    case PDT_ERR_NOMEM:
        return "PDT_ERR_NOMEM";
    case PDT_ERR_NONFINITE:
        return "PDT_ERR_NONFINITE";
    case PDT_ERR_TOO_SHORT:
        return "PDT_ERR_TOO_SHORT";
    case PDT_ERR_BOUNDS:
        return "PDT_ERR_BOUNDS";
    case PDT_ERR_NO_FORM:
        return "PDT_ERR_NO_FORM";
    case PDT_ERR_NO_EXCITATION:
        return "PDT_ERR_NO_EXCITATION";
    case PDT_ERR_STATE:
        return "PDT_ERR_STATE";
    case PDT_ERR_PV_LIMIT:
        return "PDT_ERR_PV_LIMIT";
    case PDT_ERR_OUTPUT_LIMIT:
        return "PDT_ERR_OUTPUT_LIMIT";
    case PDT_ERR_TIMEOUT:
        return "PDT_ERR_TIMEOUT";
    case PDT_ERR_SETPOINT:
        return "PDT_ERR_SETPOINT";
    case PDT_ERR_POOR_FIT:
        return "PDT_ERR_POOR_FIT";
    case PDT_ERR_UNSTABLE:
        return "PDT_ERR_UNSTABLE";
    case PDT_ERR_ABORTED:
        return "PDT_ERR_ABORTED";
    case PDT_ERR_NOT_AT_REST:
        return "PDT_ERR_NOT_AT_REST";
    case PDT_ERR_OUTLIER:
        return "PDT_ERR_OUTLIER";
    case PDT_ERR_MODEL_INVALID:
        return "PDT_ERR_MODEL_INVALID";
    case PDT_ERR_UNCERTAIN:
        return "PDT_ERR_UNCERTAIN";
    case PDT_ERR_DISTURBED:
        return "PDT_ERR_DISTURBED";
    case PDT_ERR_MS_LIMIT:
        return "PDT_ERR_MS_LIMIT";
    default:
        return "PDT_STATUS_UNKNOWN";
    }
}
