/* mm - the command-line program: a thin layer over the library. */
#include <stdio.h>
#include <string.h>

#include <mm/mm.h>

#include "commands.h"

#ifndef MM_HAVE_GLFW
int mm_cmd_view(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fputs("mm: this mm was built without GLFW, so it has no viewer: apt-get install libglfw3-dev and rebuild "
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

static void usage(FILE *f)
{
    fputs(
        "usage: mm <command> [arguments]\n"
        "\n"
        "commands:\n"
        "  bvh info FILE [--json]            joints, frames, fps, duration, channel orders, height\n"
        "  bvh fk FILE --frame K             world position of every joint at frame K (0-based)\n"
        "  bvh convert IN OUT [--order ZYX] [--scale S|auto] [--fps F]\n"
        "                                    re-write, rescale and resample a BVH file\n"
        "  bvh spans FILE [--scale S] [--low-hips 0.6] [--pad 1] [--idle-speed 0.15] [--idle-min 1]\n"
        "                 [--write CONFIG.json [--as NAME] [--no-mirror]]\n"
        "                                    lying-down, idle and locomotion frame spans (JSON); --write\n"
        "                                    adds them to a config as clips NAME and NAME_idle\n"
        "  config explain [FIELD] [--markdown]  what every database config field means\n"
        "  config check CONFIG               validate a config and find its files\n"
        "  config init TAKE... -o CONFIG     a whole config from the takes: roles, clips, speeds\n"
        "  convert BVH_DIR FBX_DIR [--batch-size 10] [--blender PATH]\n"
        "                                    BVH files to FBX through Blender, batch-size takes per file\n"
        "  import info FILE [--json]         the takes of a BVH, FBX, glTF or Collada file\n"
        "  db build CONFIG -o OUT.mmdb [--data DIR]  build a motion database (clip files are looked\n"
        "                                    for beside CONFIG, in DIR, then in $MM_DATA_DIR)\n"
        "  db info FILE [--json]             frames, dims, clips, tags, feature groups\n"
        "  db dump FILE                      everything in a database as deterministic text\n"
        "  metrics FILE.bvh [--db DB.mmdb] [--scale S|auto] [--scene SCENE.json] [-o OUT.json]\n"
        "                                    the metrics of the motion alone (docs/metrics.md)\n"
        "  moves detect FILE.bvh [--config CONFIG] [--json] [--write CONFIG.json] [--as NAME] [--no-mirror]\n"
        "                                    jumps, vaults, climbs and drops with their events; --write\n"
        "                                    adds them to a config as tagged clips\n"
        "  pfnn eval --weights DIR --x X.bin --phase P [--mode constant|linear|cubic] -o Y.bin\n"
        "                                    run the PFNN network on raw inputs (342 float32 per row)\n"
        "  synth OUTDIR [--seed N] [--fps 60]  write the built-in procedural motion set (BVH + clips.json)\n"
        "  similarity DB --from CLIP --to CLIP -o DIR [--window N] [--measure cos|euclid] [--poor S]\n"
        "                                    audit two clips: similarity CSV, heat-map PNG, poor frames\n"
        "  similarity build DB [-o TABLES] [--window N] [--measure cos|euclid] [--threads N]\n"
        "                                    fusion and link tables (default DB.sim); info TABLES [--db DB]\n"
        "  version                           print the version\n"
        "  help                              print this text\n",
        f);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; ++i)
        if (strcmp(cmd, commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
    if (strcmp(cmd, "version") == 0 || strcmp(cmd, "--version") == 0) {
        printf("mm %s\n", MM_VERSION_STRING);
        return 0;
    }
    if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        usage(stdout);
        return 0;
    }
    fprintf(stderr, "mm: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
