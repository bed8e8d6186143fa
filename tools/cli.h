/* cli.h - small helpers shared by the subcommands: argument parsing and error printing. */
#ifndef MM_TOOLS_CLI_H
#define MM_TOOLS_CLI_H

#include <stdio.h>

#include <mm/clip.h>
#include <mm/result.h>

/* Prints "mm: " + the formatted error on stderr. Returns 1 (an exit code). */
int cli_report(const mm_error *err);
/* Prints "mm <command>: message" on stderr. Returns 2 (usage error exit code). */
int cli_usage_error(const char *command, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Table-driven option parsing. Each option names where its value goes (target):
 *   CLI_FLAG    int *, set to 1 (no value follows)
 *   CLI_STRING  const char **, the next argument as it is
 *   CLI_INT     long *, a decimal int in [min, max] (cli_parse_int)
 *   CLI_DOUBLE  double *, a number in [min, max], or (min, max] with open_min (cli_parse_double)
 *   CLI_SIZE    int[2], WIDTHxHEIGHT (cli_parse_size)
 *   CLI_CUSTOM  parse(command, option, value) stores it; returns 0, or an exit code after printing
 * A bad value prints "mm COMMAND: NAME needs NEED" (need NULL on a CLI_INT: "a number from MIN to
 * MAX"; other kinds that take a value give need unless usage is given). A missing value prints the same, or,
 * when usage is given, "unknown or incomplete option" with the usage, as an unknown option does (else
 * "unknown option 'X'"). Other arguments fill args (up to max_args, the rest stay as they were; one more is
 * "unexpected argument"). Returns 0, or 2 (the usage error exit code) after printing. */
typedef enum cli_option_kind {
    CLI_FLAG,
    CLI_STRING,
    CLI_INT,
    CLI_DOUBLE,
    CLI_SIZE,
    CLI_CUSTOM
} cli_option_kind;
typedef struct cli_option cli_option;
struct cli_option {
    const char *name;
    const char *alias; /* another spelling, or NULL; messages use name */
    cli_option_kind kind;
    void *target;
    double min, max;
    int open_min;
    const char *need;
    int (*parse)(const char *command, const cli_option *option, const char *value);
};
int cli_parse_options(const char *command, int argc, char **argv, const cli_option *options, int option_count,
                      const char *usage, const char **args, int max_args);
/* A CLI_CUSTOM parser of --scale: a factor in (0, 1000], or auto (stored as 0: detect the unit);
 * target is a double. */
int cli_parse_scale(const char *command, const cli_option *option, const char *value);
/* Reads the BVH file at path as a clip in metres: scale metres per file unit, or 0 to detect the
 * unit. 0 on success; otherwise reports the error, naming the file, and returns 1. */
int cli_load_clip(const char *path, double scale, mm_clip *clip);
/* The number of elements of an array (an option table). */
#define CLI_COUNT(array) ((int)(sizeof(array) / sizeof((array)[0])))
/* Parses a whole argument as a decimal number (no hexadecimal, inf or nan) that a float holds
 * without becoming 0 or infinite (0, or a magnitude from FLT_MIN to FLT_MAX) / a decimal int in
 * range; 0 on failure. */
int cli_parse_double(const char *s, double *out);
int cli_parse_int(const char *s, long min, long max, long *out);
/* The default thread count of the commands that take --threads: the online cores, 1 to 8. */
long cli_default_threads(void);
/* Parses WIDTHxHEIGHT (each 16 to 4096); 0 on failure. */
int cli_parse_size(const char *s, int *width, int *height);
/* Output files that appear whole or not at all. cli_create opens a temporary file beside path for
 * writing and puts its name in tmp (tmp_size bytes); NULL after printing "mm: PATH: ..." when it
 * cannot; a path that is a device or a pipe (/dev/null) is opened in place instead and tmp left
 * empty. cli_commit closes f and renames the temporary file to path; when failed is non-zero, or
 * anything fails, it removes the temporary file instead. Returns 0 when path was written, else 1
 * (after printing "mm: PATH: cannot write: ...", unless failed was given). */
FILE *cli_create(const char *path, char *tmp, size_t tmp_size);
/* A temporary file written by other means (an encoder's output), removed if a signal ends the
 * program before cli_forget_temp: at most 8 at once, names shorter than CLI_TEMP_NAME_MAX. */
#define CLI_TEMP_NAME_MAX (4096 + 64)
void cli_remember_temp(const char *tmp);
void cli_forget_temp(const char *tmp);
/* The process writing them (an encoder), ended first by such a signal; 0: none. */
void cli_remember_child(long pid);
int cli_commit(FILE *f, const char *tmp, const char *path, int failed);
/* The two halves of cli_commit, for commands that write several outputs which must appear together
 * or not at all: cli_finish every one (closes f; 0 when all was written, else prints, removes tmp
 * and returns 1), and only when all succeeded cli_publish each (the rename; on failure prints,
 * removes tmp and returns 1); otherwise remove() the finished temporary files. */
int cli_finish(FILE *f, const char *tmp, const char *path);
int cli_publish(const char *tmp, const char *path);
/* Seconds on the monotonic clock (for timings that are printed, never for results). */
double cli_now(void);
/* Writes s as a JSON string literal (quotes and escapes included). */
void cli_json_string(FILE *f, const char *s);
/* The file's name without folders and extension. */
void cli_file_stem(const char *path, char *out, size_t size);
/* How a config names a clip file: relative to $MM_DATA_DIR when it is inside it, else as given. */
void cli_config_file_name(const char *path, char *out, size_t size);

/* The help (tools/help.c): one table of every command's summary and full usage (each option with its
 * default). cli_help_list prints the list of commands. cli_help prints the usage of command sub
 * (sub NULL or not one of command's subcommands: the command's own usage and the names of its
 * subcommands, or all its subcommands' usages when it has none of its own); 1 when command has
 * no entry. cli_help_known: command is in the table. cli_wants_help: argv (argv[0] the command)
 * holds --help or -h. */
void cli_help_list(FILE *f);
int cli_help(FILE *f, const char *command, const char *sub);
int cli_help_known(const char *command);
int cli_wants_help(int argc, char **argv);

#endif
