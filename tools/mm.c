/* mm - the command-line program: a thin layer over the library. */
#include <stdio.h>
#include <string.h>

#include <mm/mm.h>

#include "cli.h"
#include "commands.h"

#ifndef MM_HAVE_GLFW
int mm_cmd_view(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fputs(
        "mm: this mm was built without GLFW or Dear ImGui, so it has no viewer: apt-get install libglfw3-dev "
        "libimgui-dev and rebuild "
        "(mm render and mm simulate --video draw without a window)\n",
        stderr);
    return 1;
}
#endif

static const struct command {
    const char *name;
    int (*run)(int argc, char **argv);
} commands[] = {
    {"bvh", mm_cmd_bvh},           {"config", mm_cmd_config},
    {"convert", mm_cmd_convert},   {"db", mm_cmd_db},
    {"synth", mm_cmd_synth},       {"import", mm_cmd_import},
    {"pfnn", mm_cmd_pfnn},         {"similarity", mm_cmd_similarity},
    {"simulate", mm_cmd_simulate}, {"render", mm_cmd_render},
    {"view", mm_cmd_view},         {"moves", mm_cmd_moves},
    {"metrics", mm_cmd_metrics},
};

int main(int argc, char **argv)
{
    if (argc < 2) {
        cli_help_list(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        if (argc < 3) {
            cli_help_list(stdout);
            return 0;
        }
        if (cli_wants_help(argc - 1, argv + 1)) return cli_help(stdout, "help", NULL);
        if (cli_help(stdout, argv[2], argc > 3 ? argv[3] : NULL) == 0) return 0;
        fprintf(stderr, "mm: no command '%s' (mm help lists them)\n", argv[2]);
        return 2;
    }
    /* mm COMMAND [SUBCOMMAND] ... --help: the usage from the table, before the command parses */
    if (cli_help_known(cmd) && cli_wants_help(argc - 1, argv + 1))
        return cli_help(stdout, cmd, argc > 2 ? argv[2] : NULL);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (strcmp(cmd, commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
    if (strcmp(cmd, "version") == 0 || strcmp(cmd, "--version") == 0) {
        /* the program's version, the library's it runs with, and the database format it reads */
        printf("mm %s (library %s, database format %d)\n", MM_VERSION_STRING, mm_version_string(),
               MM_DB_VERSION);
        return 0;
    }
    fprintf(stderr, "mm: unknown command '%s'\n", cmd);
    cli_help_list(stderr);
    return 2;
}
