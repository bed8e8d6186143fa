/* mm simulate --skeleton: the output in the game's skeleton (sim_skeleton.h). The map file:
 *   {"pairs": {"GAME_JOINT": "DATABASE_JOINT", ...},
 *    "follow": [{"joint": "GAME_JOINT", "follows": "DATABASE_JOINT", "weight": 0.5, "twist": true}, ...],
 *    "root": false, "game_lengths": true}
 * every field optional (docs/embedding.md, "The game's skeleton"). */
#include "sim_skeleton.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/clip.h>

#include "cli.h"

/* A map file's joints at most (pairs and followers each): far above any skeleton's. */
#define MAP_MAX_ENTRIES MM_MAX_JOINTS

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = NULL;
    if (fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        if (size >= 0 && size < (1L << 24) && fseek(f, 0, SEEK_SET) == 0 &&
            (text = malloc((size_t)size + 1))) {
            if (fread(text, 1, (size_t)size, f) != (size_t)size) {
                free(text);
                text = NULL;
            } else {
                text[size] = 0;
            }
        }
    }
    fclose(f);
    return text;
}

static int map_error(const char *path, const char *what)
{
    fprintf(stderr, "mm: %s: %s\n", path, what);
    return 1;
}

/* Fills d from the map file's JSON (its strings point into root). */
static int parse_map(const char *path, const cJSON *root, mm_skeleton_map_desc *d,
                     mm_skeleton_map_pair *pairs, mm_skeleton_map_follow *follow)
{
    if (!cJSON_IsObject(root)) return map_error(path, "a skeleton map is a JSON object");
    for (const cJSON *item = root->child; item; item = item->next) {
        const char *key = item->string;
        char message[256];
        if (strcmp(key, "pairs") == 0) {
            if (!cJSON_IsObject(item))
                return map_error(path, "\"pairs\" must be an object {\"GAME\": \"DATABASE\"}");
            for (const cJSON *p = item->child; p; p = p->next) {
                if (!cJSON_IsString(p)) {
                    snprintf(message, sizeof message, "\"pairs\".\"%.64s\" must be a database joint's name",
                             p->string);
                    return map_error(path, message);
                }
                if (d->pair_count == MAP_MAX_ENTRIES) return map_error(path, "\"pairs\": too many");
                pairs[d->pair_count].game = p->string;
                pairs[d->pair_count++].database = p->valuestring;
            }
        } else if (strcmp(key, "follow") == 0) {
            if (!cJSON_IsArray(item)) return map_error(path, "\"follow\" must be an array");
            int k = 0;
            for (const cJSON *f = item->child; f; f = f->next, ++k) {
                const cJSON *joint = cJSON_GetObjectItemCaseSensitive(f, "joint");
                const cJSON *follows = cJSON_GetObjectItemCaseSensitive(f, "follows");
                const cJSON *weight = cJSON_GetObjectItemCaseSensitive(f, "weight");
                const cJSON *twist = cJSON_GetObjectItemCaseSensitive(f, "twist");
                if (!cJSON_IsString(joint) || !cJSON_IsString(follows) ||
                    (weight && !cJSON_IsNumber(weight)) || (twist && !cJSON_IsBool(twist))) {
                    snprintf(message, sizeof message,
                             "\"follow\"[%d] needs \"joint\" and \"follows\" (names), \"weight\" a number, "
                             "\"twist\" true or false",
                             k);
                    return map_error(path, message);
                }
                if (d->follow_count == MAP_MAX_ENTRIES) return map_error(path, "\"follow\": too many");
                mm_skeleton_map_follow *out = &follow[d->follow_count++];
                out->game = joint->valuestring;
                out->database = follows->valuestring;
                out->weight = weight ? (float)weight->valuedouble : 1.0f;
                out->twist = twist ? cJSON_IsTrue(twist) : false;
            }
        } else if (strcmp(key, "root") == 0 || strcmp(key, "game_lengths") == 0) {
            if (!cJSON_IsBool(item)) {
                snprintf(message, sizeof message, "\"%s\" must be true or false", key);
                return map_error(path, message);
            }
            if (key[0] == 'r')
                d->with_root = cJSON_IsTrue(item);
            else
                d->game_lengths = cJSON_IsTrue(item);
        } else {
            snprintf(message, sizeof message, "unknown field \"%.64s\" (pairs, follow, root, game_lengths)",
                     key);
            return map_error(path, message);
        }
    }
    return 0;
}

int sim_skeleton_open(sim_skeleton *s, const char *path, const char *map_path, const mm_database *db)
{
    memset(s, 0, sizeof *s);
    mm_clip game;
    if (cli_load_clip(path, 0.0, &game) != 0) return 1;
    mm_skeleton_map_desc d;
    memset(&d, 0, sizeof d);
    d.game_lengths = true; /* a game's BVH keeps its own bone lengths */
    cJSON *json = NULL;
    mm_skeleton_map_pair *pairs = calloc(MAP_MAX_ENTRIES, sizeof *pairs);
    mm_skeleton_map_follow *follow = calloc(MAP_MAX_ENTRIES, sizeof *follow);
    int status = pairs && follow ? 0 : map_error(path, "out of memory");
    if (status == 0 && map_path) {
        char *text = read_text(map_path);
        if (!text) {
            status = map_error(map_path, "cannot read the skeleton map");
        } else if (!(json = cJSON_Parse(text))) {
            status = map_error(map_path, "not valid JSON");
        } else {
            status = parse_map(map_path, json, &d, pairs, follow);
        }
        free(text);
    }
    d.pairs = pairs;
    d.follow = follow;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (status == 0 && mm_skeleton_map_init(&s->map, db, &game.skeleton, &d, &err) != MM_OK) {
        snprintf(err.file, sizeof err.file, "%s", map_path && strstr(err.message, "pair") ? map_path : path);
        status = cli_report(&err);
    }
    cJSON_Delete(json);
    free(pairs);
    free(follow);
    mm_clip_free(&game);
    if (status == 0 && !(s->world = malloc(sizeof(mm_xform) * (size_t)s->map.joint_count)))
        status = map_error(path, "out of memory");
    if (status != 0) sim_skeleton_close(s);
    return status;
}

int sim_skeleton_copy(const sim_skeleton *s, mm_skeleton *out)
{
    if (mm_skeleton_init(out, s->map.joint_count, NULL) != MM_OK) return 1;
    memcpy(out->joints, s->map.joints, sizeof(mm_joint) * (size_t)s->map.joint_count);
    return 0;
}

void sim_skeleton_pose(sim_skeleton *s, const mm_character *c, mm_quat *rotations, mm_vec3 *positions)
{
    mm_skeleton_map_pose(&s->map, c->global, c->local_rotations, rotations, positions, s->world);
}

void sim_skeleton_close(sim_skeleton *s)
{
    mm_skeleton_map_free(&s->map);
    free(s->world);
    memset(s, 0, sizeof *s);
}
