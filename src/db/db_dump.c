/* Deterministic text form of a database, for diffs and bug reports. */
#include <mm/database_build.h>

#include <ctype.h>
#include <math.h>
#include <string.h>

#include <mm/gait.h>

#include "db/process.h"
#include "io/text.h"

static void num(FILE *out, double v)
{
    char buf[64];
    mm__format_number(buf, sizeof buf, v, 9);
    fputc(' ', out);
    fputs(buf, out);
}

static void vec(FILE *out, mm_vec3 v)
{
    num(out, v.x);
    num(out, v.y);
    num(out, v.z);
}

/* The settings section: every field, set or not, with the set bits in hex. */
static void dump_settings(const mm_database *db, FILE *out)
{
    const mm_database_settings *s = db->settings;
    fprintf(out, "settings weights set %x position_set %x velocity_set %x\n", (unsigned)s->weight_set,
            (unsigned)s->position_set, (unsigned)s->velocity_set);
    fputs("settings joint_position_weights", out);
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) num(out, s->joint_position_weights[b]);
    fputs("\nsettings joint_velocity_weights", out);
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) num(out, s->joint_velocity_weights[b]);
    fputs("\nsettings body_velocity_weight", out);
    num(out, s->body_velocity_weight);
    fputs(" position_multiplier", out);
    num(out, s->position_multiplier);
    fputs(" angle_multiplier", out);
    num(out, s->angle_multiplier);
    fprintf(out, "\nsettings runtime set %x", (unsigned)s->set);
    const char *names[8] = {
        "pose_trajectory_ratio", "next_pose_favour",    "loop_anim_favour", "continuing_bias",
        "search_interval",       "transition_halflife", "idle_speed",       "sync_halflife"};
    const float values[8] = {
        s->pose_trajectory_ratio, s->next_pose_favour,    s->loop_anim_favour, s->continuing_bias,
        s->search_interval,       s->transition_halflife, s->idle_speed,       s->sync_halflife};
    for (int k = 0; k < 8; ++k) {
        fprintf(out, " %s", names[k]);
        num(out, values[k]);
    }
    fprintf(out, " distance_matching %u warping %u contact_favour", (unsigned)s->distance_matching,
            (unsigned)s->warping);
    num(out, s->contact_favour);
    fprintf(out, " speed_envelope %u\n", (unsigned)s->speed_envelope);
    const mm_runtime_gait *gaits[3] = {&s->walk, &s->run, &s->crouch};
    const char *gait_names[3] = {"walk", "run", "crouch"};
    for (int g = 0; g < 3; ++g) {
        const mm_runtime_gait *a = gaits[g];
        fprintf(out, "settings %s set %x forward_speed", gait_names[g], (unsigned)a->set);
        num(out, a->forward_speed);
        fputs(" side_speed", out);
        num(out, a->side_speed);
        fputs(" backward_speed", out);
        num(out, a->backward_speed);
        fputs(" velocity_halflife", out);
        num(out, a->velocity_halflife);
        fputs(" rotation_halflife", out);
        num(out, a->rotation_halflife);
        fputc('\n', out);
    }
    for (int g = 0; g < MM_SETTINGS_ENVELOPE_GAITS; ++g) {
        fprintf(out, "settings envelope %d", g);
        for (int k = 0; k < MM_SETTINGS_ENVELOPE_BINS; ++k) num(out, s->envelope[g][k]);
        fputc('\n', out);
    }
    const char *roles[MM_ROLE_COUNT] = {"hips",      "left_foot", "right_foot", "left_toe",
                                        "right_toe", "left_hand", "right_hand", "head"};
    fputs("settings roles", out);
    for (int k = 0; k < MM_ROLE_COUNT; ++k) fprintf(out, " %s %d", roles[k], (int)s->roles[k]);
    fputc('\n', out);
}

mm_result mm_database_dump(const mm_database *db, FILE *out)
{
    if (!db || !out || !db->data) return MM_ERR_INVALID_ARGUMENT;
    mm_quat q[MM_MAX_JOINTS];
    mm_vec3 p[MM_MAX_JOINTS];
    fprintf(out, "mmdb version %d\n", MM_DB_VERSION);
    fprintf(out, "frames %d joints %d clips %d tags %d groups %d dims %d dims_padded %d interval",
            db->frame_count, db->joint_count, db->clip_count, db->tag_count, db->group_count, db->dims,
            db->dims_padded);
    num(out, db->interval);
    fputc('\n', out);
    if (db->pose_codec == MM_POSE_SEGMENTS) {
        const mm_db_compressed_poses *c = &db->compressed;
        fprintf(out, "poses segments segment_frames %d segments %d translating %d bytes %zu error_bound",
                c->segment_frames, c->segment_count, c->translating_count, mm_database_pose_bytes(db));
        num(out, c->error_bound);
        fputs(" max_error", out);
        num(out, c->max_error);
        fputc('\n', out);
    } else {
        fprintf(out, "poses floats bytes %zu\n", mm_database_pose_bytes(db));
    }
    for (int j = 0; j < db->joint_count; ++j) {
        const mm_joint *jt = &db->joints[j];
        fprintf(out, "joint %d %s parent %d flags %u order %d offset", j, jt->name, jt->parent, jt->flags,
                (int)jt->order);
        vec(out, jt->offset);
        if (jt->has_end_site) {
            fputs(" end_site", out);
            vec(out, jt->end_site);
        }
        fputc('\n', out);
    }
    for (int t = 0; t < db->tag_count; ++t) fprintf(out, "tag %d %s\n", t, db->tag_names[t]);
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        fprintf(out, "group %d %s kind %s bone %d offset %d dims %d time", g, grp->name,
                mm_feature_kind_name((mm_feature_kind)grp->kind), grp->bone, grp->offset, grp->dims);
        num(out, grp->time);
        fputs(" weight", out);
        num(out, grp->weight);
        fputs(" scale", out);
        num(out, grp->scale);
        fputc('\n', out);
    }
    if (db->settings) dump_settings(db, out);
    for (int d = 0; d < db->dims_padded; ++d) {
        fprintf(out, "dim %d mean", d);
        num(out, db->feature_mean[d]);
        fputs(" scale", out);
        num(out, db->feature_scale[d]);
        fputc('\n', out);
    }
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        fprintf(out, "clip %d %s first %d frames %d type %s loop %d mirrored %d source %d blend %d %d", c,
                k->name, k->first_frame, k->frame_count, k->type == MM_CLIP_IDLE ? "idle" : "locomotion",
                k->loop, k->mirrored, k->source, k->blend_left, k->blend_right);
        num(out, k->blend_weight);
        fputs(" start", out);
        num(out, k->source_start);
        fputc('\n', out);
    }
    static const char *kinds[] = {"none", "stop", "pivot"};
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_distance_clip *d = &db->distance_clips[c];
        fprintf(out, "distance %d path_length", c);
        num(out, d->path_length);
        fputs(" stop_speed", out);
        num(out, d->stop_speed);
        fprintf(out, " segments %d first %d\n", d->segment_count, d->first_segment);
        for (int s = 0; s < d->segment_count; ++s) {
            const mm_distance_segment *g = &db->distance_segments[d->first_segment + s];
            fprintf(out, "  segment %d first %d frames %d marker %d kind %s marker_travelled", s,
                    g->first_frame, g->frame_count, g->marker_frame, kinds[g->kind]);
            num(out, g->marker_travelled);
            fputc('\n', out);
        }
    }
    for (int f = 0; f < db->frame_count; ++f) {
        fprintf(out, "frame %d clip %d next %d tags %llx contacts %x root_velocity", f, db->frame_clip[f],
                db->frame_next[f], (unsigned long long)db->frame_tags[f], db->contacts[f]);
        vec(out, db->root_velocity[f]);
        fputs(" yaw_rate", out);
        num(out, db->root_angular_velocity[f]);
        fputs(" travelled", out);
        num(out, db->distance_travelled[f]);
        fputs(" distance", out);
        num(out, db->distance_signed[f]);
        fputs(" features", out);
        for (int d = 0; d < db->dims; ++d) num(out, mm_database_feature_raw(db, f, d));
        fputc('\n', out);
        mm_database_local_pose(db, f, q, p);
        fputs("  pose", out);
        for (int j = 0; j < db->joint_count; ++j) {
            num(out, q[j].x);
            num(out, q[j].y);
            num(out, q[j].z);
            num(out, q[j].w);
            if (db->joints[j].flags & MM_JOINT_TRANSLATES) vec(out, p[j]);
        }
        fputc('\n', out);
    }
    return ferror(out) ? MM_ERR_IO : MM_OK;
}

/* ---- speed summary ---------------------------------------------------------------------- */

static int same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

static mm_speed_percentiles percentiles(float *v, int n)
{
    mm_speed_percentiles p = {n, 0.0f, 0.0f, 0.0f};
    if (n > 0) { /* mm__quantile sorts: the three from one sort */
        p.p10 = mm__quantile(v, n, 0.1f);
        p.p50 = v[(int)floorf(0.5f * (float)(n - 1))];
        p.p90 = v[(int)floorf(0.9f * (float)(n - 1))];
    }
    return p;
}

/* The frames of one kind into s: of locomotion clips tagged with tag, or of locomotion clips
 * without any of gait_tags (tag 0), or of idle clips (idle 1). v: scratch of 3 x frame_count. */
static void summarize(const mm_database *db, uint64_t tag, uint64_t gait_tags, int idle, float *v,
                      mm_speed_summary *s)
{
    int n = db->frame_count, count[3] = {0, 0, 0};
    float *dir[3] = {v, v + n, v + 2 * (size_t)n};
    s->frames = s->still = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        if ((k->type == MM_CLIP_IDLE) != idle) continue;
        for (int f = k->first_frame; f < k->first_frame + k->frame_count; ++f) {
            uint64_t tags = db->frame_tags ? db->frame_tags[f] : 0;
            if (!idle && (tag ? !(tags & tag) : (tags & gait_tags) != 0)) continue;
            ++s->frames;
            mm_vec3 u = db->root_velocity[f];
            float speed = sqrtf(u.x * u.x + u.z * u.z);
            if (!(speed >= MM_SPEED_SUMMARY_STILL)) {
                ++s->still;
                continue;
            }
            int d = u.z >= fabsf(u.x) ? 0 : -u.z >= fabsf(u.x) ? 2 : 1; /* forward, backward, side */
            dir[d][count[d]++] = speed;
        }
    }
    s->forward = percentiles(dir[0], count[0]);
    s->side = percentiles(dir[1], count[1]);
    s->backward = percentiles(dir[2], count[2]);
}

mm_result mm_database_speed_summary(const mm_database *db, const mm_allocator *a,
                                    mm_speed_summary out[MM_SPEED_SUMMARY_MAX], int *count)
{
    if (count) *count = 0;
    if (!db || !out || !count || !db->root_velocity) return MM_ERR_INVALID_ARGUMENT;
    if (db->frame_count <= 0) return MM_OK;
    float *v = (float *)mm_alloc_array(a, 3 * (size_t)db->frame_count, sizeof(float));
    if (!v) return MM_ERR_OUT_OF_MEMORY;
    /* the gait tags: tags named after a gait, any case */
    uint64_t gait_tags = 0, gait_tag[MM_GAIT_COUNT];
    int gait_index[MM_GAIT_COUNT];
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        gait_tag[g] = 0;
        gait_index[g] = -1;
        for (int t = 0; t < db->tag_count && t < 64; ++t)
            if (same_name_any_case(db->tag_names[t], mm_gait_name((mm_gait)g))) {
                gait_tag[g] |= (uint64_t)1 << t;
                if (gait_index[g] < 0) gait_index[g] = t;
            }
        gait_tags |= gait_tag[g];
    }
    int n = 0;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        if (!gait_tag[g]) continue;
        mm_speed_summary *s = &out[n];
        memset(s, 0, sizeof *s);
        snprintf(s->name, sizeof s->name, "%s", db->tag_names[gait_index[g]]);
        summarize(db, gait_tag[g], gait_tags, 0, v, s);
        n += s->frames > 0;
    }
    for (int idle = 0; idle < 2; ++idle) {
        mm_speed_summary *s = &out[n];
        memset(s, 0, sizeof *s);
        snprintf(s->name, sizeof s->name, "%s", idle ? "idle" : "locomotion");
        summarize(db, 0, gait_tags, idle, v, s);
        n += s->frames > 0;
    }
    mm_free(a, v);
    *count = n;
    return MM_OK;
}
