/* Reading a model from JSON (model_json.c). */
#ifndef PDTCLI_MODEL_JSON_H
#define PDTCLI_MODEL_JSON_H

#include "cli.h"

/* The whole file at path ("-": standard input), NUL-terminated, malloc'ed;
 * NULL when it cannot be read. */
char *pdtcli_slurp(const char *path);

/* The model of identify's JSON (or of autotune-sim's "ident", or just the
 * model's own fields) in the file at path into *m, its "fit" into *fit
 * (100 when absent), its flags as tune_json_flags names them into flags
 * (NULL: not asked for). Returns how many flags. Ends the program with a
 * message naming cmd when the file cannot be read or holds no valid model. */
int pdtcli_model_from_json(const char *cmd, const char *path, pdt_model_t *m, double *fit,
                           char *flags, size_t flags_len);

#endif /* PDTCLI_MODEL_JSON_H */
