/*
 * pdtfit: the command line. `pdtfit identify --model fopdt FILE.csv` reads
 * one record of a plant, identifies a FOPDT or SOPDT model with the library
 * and prints it as one JSON object; reduce, tune and autotune-sim do the
 * rest of the library's work from the shell. One source per subcommand
 * (cmd_*.c), the option parser in opt.c.
 *
 * Exit status: 0 success, 1 the library refused (or the host failed), 2 a
 * usage or input error, 3 identify printed a model it warns about. Every
 * error is one line on stderr starting "pdtfit: ".
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"

const char *cli_argv0 = "pdtfit";

static const struct command {
    const char *name;
    int (*run)(int argc, char **argv);
} commands[] = {
    {"identify", cmd_identify},         {"reduce", cmd_reduce},   {"tune", cmd_tune},
    {"autotune-sim", cmd_autotune_sim}, {"monitor", cmd_monitor},
};

int main(int argc, char **argv)
{
    if (argc > 0 && argv[0]) cli_argv0 = argv[0];
    if (argc < 2)
        cli_fail(EXIT_USAGE, "missing command (usage: pdtfit identify --model fopdt|sopdt "
                             "FILE.csv; see pdtfit --help)");
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0)
        cli_help(CMD_ALL);
    if (strcmp(cmd, "--version") == 0) {
        printf("pdtfit %s (pdt_real_t = %s)\n", PDT_VERSION_STRING,
               sizeof(pdt_real_t) == sizeof(float) ? "float" : "double");
        cli_flush();
        return 0;
    }
    for (size_t k = 0; k < sizeof commands / sizeof commands[0]; k++)
        if (strcmp(cmd, commands[k].name) == 0) return commands[k].run(argc - 2, argv + 2);
    cli_fail(EXIT_USAGE, "unknown command '%s' (see pdtfit --help)", cmd);
}
