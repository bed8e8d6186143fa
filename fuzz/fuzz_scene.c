/* libFuzzer target: scenes in JSON. Any bytes parse or fail with a message; a parsed scene
 * answers ray casts, ground probes and obstacle measures with finite results, and writes out
 * to a scene that parses back the same. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/scene_json.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_hit(const mm_scene_hit *h, int may_be_negative)
{
    if (!isfinite(h->distance) || !isfinite(h->point.x) || !isfinite(h->point.y) || !isfinite(h->point.z) ||
        !isfinite(h->normal.x) || !isfinite(h->normal.y) || !isfinite(h->normal.z) ||
        (!may_be_negative && h->distance < 0.0f))
        __builtin_trap();
}

static mm_scene scene, again; /* large: kept off the stack */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_scene_parse_json((const char *)data, size, "fuzz.json", &scene, &err) != MM_OK) {
        if (err.message[0] == 0) __builtin_trap(); /* every failure must say why */
        return 0;
    }
    /* queries from a few places, towards each box and along the axes */
    mm_scene_hit hit;
    const mm_vec3 dirs[4] = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}, {0.3f, -0.2f, -1}};
    for (int b = -1; b < scene.box_count && b < 8; ++b) {
        mm_vec3 from = b < 0 ? mm_vec3_make(0, 1, 0) : mm_scene_box_centre(&scene.boxes[b]);
        from.z -= 2.0f;
        for (int k = 0; k < 4; ++k) {
            if (mm_scene_raycast(&scene, from, dirs[k], INFINITY, &hit)) check_hit(&hit, 0);
            if (mm_scene_raycast(&scene, from, dirs[k], 3.0f, &hit)) check_hit(&hit, 0);
        }
        if (mm_scene_ground_probe(&scene, from, 0.3f, INFINITY, &hit)) check_hit(&hit, 1); /* step up: < 0 */
        mm_obstacle o;
        if (mm_scene_measure_obstacle(&scene, from, dirs[0], NULL, &o)) {
            check_hit(&o.hit, 0);
            if (!isfinite(o.height) || !isfinite(o.depth) || o.depth < 0.0f) __builtin_trap();
        }
    }
    /* round trip */
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f) return 0;
    if (mm_scene_write_json(&scene, f) != MM_OK) __builtin_trap();
    fclose(f);
    if (mm_scene_parse_json(text, len, "again.json", &again, &err) != MM_OK) __builtin_trap();
    free(text);
    if (again.box_count != scene.box_count || again.ground != scene.ground) __builtin_trap();
    for (int i = 0; i < scene.box_count; ++i)
        if (memcmp(&again.boxes[i].position, &scene.boxes[i].position, sizeof(mm_vec3)) != 0 ||
            memcmp(&again.boxes[i].size, &scene.boxes[i].size, sizeof(mm_vec3)) != 0 ||
            fabsf(again.boxes[i].yaw - scene.boxes[i].yaw) > 1e-6f * (1.0f + fabsf(scene.boxes[i].yaw)))
            __builtin_trap();
    return 0;
}
