/* What a database's locomotion covers, per gait and direction of travel (mm/speed_envelope.h). */
#include <mm/speed_envelope.h>

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/character.h>
#include <mm/database_build.h>
#include <mm/gait.h>

static int same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

/* The tags of each gait: the database's tags named after it, in any case. */
static void gait_tags(const mm_database *db, uint64_t tags[MM_GAIT_COUNT])
{
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        tags[g] = 0;
        for (int t = 0; t < db->tag_count && t < MM_MAX_TAGS; ++t)
            if (same_name_any_case(db->tag_names[t], mm_gait_name((mm_gait)g))) tags[g] |= (uint64_t)1 << t;
    }
}

static int descending(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x < y) - (x > y);
}

/* The angle from a to b, in (-pi, pi]. */
static float angle_between(float a, float b)
{
    float d = fmodf(b - a, 2.0f * (float)MM_PI);
    if (d > (float)MM_PI) d -= 2.0f * (float)MM_PI;
    if (d <= -(float)MM_PI) d += 2.0f * (float)MM_PI;
    return d;
}

mm_result mm_speed_envelope_measure(const mm_database *db, const mm_allocator *allocator,
                                    mm_speed_envelope out[MM_GAIT_COUNT])
{
    if (!db || !out) return MM_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof(mm_speed_envelope) * MM_GAIT_COUNT);
    if (db->frame_count < 1 || !db->root_velocity || !(db->interval > 0.0f)) return MM_OK;
    float *speed = (float *)mm_alloc_array(allocator, (size_t)db->frame_count, sizeof(float));
    float *direction = (float *)mm_alloc_array(allocator, (size_t)db->frame_count, sizeof(float));
    float *window = (float *)mm_alloc_array(allocator, (size_t)db->frame_count, sizeof(float));
    if (!speed || !direction || !window) {
        mm_free(allocator, speed);
        mm_free(allocator, direction);
        mm_free(allocator, window);
        return MM_ERR_OUT_OF_MEMORY;
    }
    for (int f = 0; f < db->frame_count; ++f) {
        mm_vec3 u = db->root_velocity[f];
        speed[f] = sqrtf(u.x * u.x + u.z * u.z);
        direction[f] = atan2f(u.x, u.z);
    }
    mm_search_params params;
    mm_character_default_params(db, &params);
    uint64_t tags[MM_GAIT_COUNT], all = 0;
    gait_tags(db, tags);
    for (int g = 0; g < MM_GAIT_COUNT; ++g) all |= tags[g];
    /* the frames a bin's speed needs: a whole number, at least one */
    int need = (int)ceilf(MM_SPEED_ENVELOPE_COVER_SECONDS / db->interval - 1e-3f);
    if (need < 1) need = 1;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        uint64_t excluded = params.excluded_tags | (all & ~tags[g]);
        for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k) {
            float centre = 2.0f * (float)MM_PI * (float)k / (float)MM_SPEED_ENVELOPE_BINS;
            int n = 0;
            for (int c = 0; c < db->clip_count; ++c) {
                const mm_db_clip *clip = &db->clips[c];
                if (clip->type == MM_CLIP_IDLE) continue;
                for (int f = clip->first_frame; f < clip->first_frame + clip->frame_count; ++f) {
                    if (db->frame_tags && (db->frame_tags[f] & excluded)) continue;
                    if (!(speed[f] >= MM_SPEED_SUMMARY_STILL)) continue;
                    if (fabsf(angle_between(centre, direction[f])) <= MM_SPEED_ENVELOPE_WINDOW)
                        window[n++] = speed[f];
                }
            }
            if (n < need) continue;
            qsort(window, (size_t)n, sizeof(float), descending);
            out[g].speeds[k] = fminf(window[need - 1], MM_SPEED_ENVELOPE_MAX);
        }
    }
    mm_free(allocator, speed);
    mm_free(allocator, direction);
    mm_free(allocator, window);
    return MM_OK;
}
