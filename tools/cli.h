/* cli.h - small helpers shared by the subcommands: argument parsing and error printing. */
#ifndef MM_TOOLS_CLI_H
#define MM_TOOLS_CLI_H

#include <stdio.h>

#include <mm/result.h>

/* Prints "mm: " + the formatted error on stderr. Returns 1 (an exit code). */
int cli_report(const mm_error *err);
/* Prints "mm <command>: message" on stderr. Returns 2 (usage error exit code). */
int cli_usage_error(const char *command, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
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
 * cannot. cli_commit closes f and renames the temporary file to path; when failed is non-zero, or
 * anything fails, it removes the temporary file instead. Returns 0 when path was written, else 1
 * (after printing "mm: PATH: cannot write: ...", unless failed was given). */
FILE *cli_create(const char *path, char *tmp, size_t tmp_size);
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

#endif
