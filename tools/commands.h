/* commands.h - the subcommands of the mm program. Each takes argv with argv[0] the subcommand's
 * name, prints errors on stderr, and returns the process exit code (0 on success). */
#ifndef MM_TOOLS_COMMANDS_H
#define MM_TOOLS_COMMANDS_H

int mm_cmd_bvh(int argc, char **argv);
/* mm bvh spans (tools/cmd_bvh_spans.c) */
int mm_cmd_bvh_spans(int argc, char **argv);
int mm_cmd_config(int argc, char **argv);
int mm_cmd_convert(int argc, char **argv);
int mm_cmd_db(int argc, char **argv);
int mm_cmd_import(int argc, char **argv);
/* mm metrics (tools/cmd_metrics.c) */
int mm_cmd_metrics(int argc, char **argv);
/* mm moves detect (tools/cmd_moves.c) */
int mm_cmd_moves(int argc, char **argv);
int mm_cmd_pfnn(int argc, char **argv);
/* mm pfnn run (tools/cmd_pfnn_run.c) */
int mm_cmd_pfnn_run(int argc, char **argv);
int mm_cmd_render(int argc, char **argv);
int mm_cmd_similarity(int argc, char **argv);
int mm_cmd_simulate(int argc, char **argv);
int mm_cmd_synth(int argc, char **argv);
int mm_cmd_view(int argc, char **argv);

#endif
