/* What a database lacks for the runtime (mm/diagnose.h). */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <mm/character.h>
#include <mm/diagnose.h>
#include <mm/gait.h>
#include <mm/posture.h>
#include <mm/trajectory.h>

#include "db/process.h"
#include "db/standing.h"

static const char *const code_names[MM_DIAG_CODE_COUNT] = {
    "no_idle", "speed_not_covered", "no_stops",        "no_starts",     "role_missing",
    "height",  "postures_left_out", "postures_tagged", "speed_envelope"};

const char *mm_diagnostic_code_name(mm_diagnostic_code code)
{
    return (unsigned)code < MM_DIAG_CODE_COUNT ? code_names[code] : NULL;
}

#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
static void
add(mm_diagnosis *d, mm_diagnostic_code code, const char *fmt, ...)
{
    if (d->count >= MM_DIAGNOSE_MAX) return;
    mm_diagnostic *item = &d->items[d->count++];
    item->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(item->message, sizeof item->message, fmt, ap);
    va_end(ap);
}

static int same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

static const char *const direction_names[3] = {"forward", "side", "backward"};

/* The gait speeds: the settings' where they set one, else the runtime's defaults. */
static void runtime_speeds(const mm_database *db, mm_speed_coverage out[MM_DIAGNOSE_SPEEDS])
{
    mm_trajectory_desc defaults;
    mm_trajectory_defaults(&defaults);
    const mm_database_settings *s = db->settings;
    for (int g = 0; g < 2; ++g) {
        const mm_runtime_gait *set = s ? (g == 0 ? &s->walk : &s->run) : NULL;
        const mm_gait_params *def = &defaults.gaits[g == 0 ? MM_GAIT_WALK : MM_GAIT_RUN];
        const unsigned bits[3] = {MM_RUNTIME_FORWARD_SPEED, MM_RUNTIME_SIDE_SPEED, MM_RUNTIME_BACKWARD_SPEED};
        const float given[3] = {set ? set->forward_speed : 0, set ? set->side_speed : 0,
                                set ? set->backward_speed : 0};
        const float fallback[3] = {def->forward_speed, def->side_speed, def->backward_speed};
        for (int d = 0; d < 3; ++d) {
            mm_speed_coverage *c = &out[3 * g + d];
            memset(c, 0, sizeof *c);
            c->gait = g == 0 ? MM_GAIT_WALK : MM_GAIT_RUN;
            c->direction = d;
            c->from_settings = set && (set->set & bits[d]);
            c->speed = c->from_settings ? given[d] : fallback[d];
        }
    }
}

/* Each gait speed against the locomotion frames the gait may play (v: scratch of frame_count). */
static void cover_speeds(const mm_database *db, float *v, mm_speed_coverage out[MM_DIAGNOSE_SPEEDS])
{
    mm_search_params params;
    mm_character_default_params(db, &params);
    uint64_t gait_tag[MM_GAIT_COUNT], gait_tags = 0;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        gait_tag[g] = 0;
        for (int t = 0; t < db->tag_count && t < 64; ++t)
            if (same_name_any_case(db->tag_names[t], mm_gait_name((mm_gait)g)))
                gait_tag[g] |= (uint64_t)1 << t;
        gait_tags |= gait_tag[g];
    }
    for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
        mm_speed_coverage *c = &out[k];
        uint64_t excluded = params.excluded_tags | (gait_tags & ~gait_tag[c->gait]);
        int n = 0;
        for (int ci = 0; ci < db->clip_count; ++ci) {
            const mm_db_clip *clip = &db->clips[ci];
            if (clip->type == MM_CLIP_IDLE) continue;
            for (int f = clip->first_frame; f < clip->first_frame + clip->frame_count; ++f) {
                if (db->frame_tags && (db->frame_tags[f] & excluded)) continue;
                mm_vec3 u = db->root_velocity[f];
                float speed = sqrtf(u.x * u.x + u.z * u.z);
                if (!(speed >= MM_SPEED_SUMMARY_STILL)) continue;
                int d = u.z >= fabsf(u.x) ? 0 : -u.z >= fabsf(u.x) ? 2 : 1;
                if (d != c->direction) continue;
                v[n++] = speed;
                c->near +=
                    speed >= c->speed / MM_DIAGNOSE_SPEED_BAND && speed <= c->speed * MM_DIAGNOSE_SPEED_BAND;
            }
        }
        c->frames = n;
        if (n > 0) {
            c->p10 = mm__quantile(v, n, 0.1f); /* sorts v */
            c->p50 = v[(int)floorf(0.5f * (float)(n - 1))];
            c->p90 = v[(int)floorf(0.9f * (float)(n - 1))];
        }
        c->covered = !(c->speed > 0) || (float)c->near * db->interval >= MM_DIAGNOSE_COVER_SECONDS;
    }
}

/* The speed envelopes (the settings', else measured now) and each gait speed's envelope that way. */
static mm_result envelopes(const mm_database *db, const mm_allocator *a, mm_diagnosis *out)
{
    const mm_database_settings *s = db->settings;
    if (s) {
        for (int g = 0; g < MM_GAIT_COUNT; ++g)
            memcpy(out->envelope[g].speeds, s->envelope[g], sizeof out->envelope[g].speeds);
        out->bounded = !(s->set & MM_RUNTIME_SPEED_ENVELOPE) || s->speed_envelope;
    } else {
        mm_result r = mm_speed_envelope_measure(db, a, out->envelope);
        if (r != MM_OK) return r;
        out->bounded = false; /* a database made in code: the character has no settings to take it from */
    }
    mm_trajectory_desc d;
    memset(&d, 0, sizeof d);
    d.bounded = true;
    memcpy(d.envelopes, out->envelope, sizeof d.envelopes);
    const float way[3][2] = {
        {0.0f, 0.0f}, {0.5f * (float)MM_PI, -0.5f * (float)MM_PI}, {(float)MM_PI, (float)MM_PI}};
    for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
        mm_speed_coverage *c = &out->speeds[k];
        c->envelope = fminf(mm_trajectory_envelope_speed(&d, (mm_gait)c->gait, way[c->direction][0]),
                            mm_trajectory_envelope_speed(&d, (mm_gait)c->gait, way[c->direction][1]));
    }
    return MM_OK;
}

/* The standing height (mm_diagnosis.height) over at most 4096 frames evenly spread; v: scratch of
 * frame_count, g: of joint_count. */
static float standing_height(const mm_database *db, float *v, mm_xform *g)
{
    int n = db->frame_count, jc = db->joint_count, step = n > 4096 ? n / 4096 : 1, count = 0;
    int head = db->settings ? db->settings->roles[MM_ROLE_HEAD] : -1;
    mm_quat rot[MM_MAX_JOINTS];
    mm_vec3 pos[MM_MAX_JOINTS];
    for (int f = 0; f < n; f += step) {
        mm_database_local_pose(db, f, rot, pos);
        g[0].rotation = rot[0];
        g[0].translation = pos[0];
        mm_skeleton_global_from(db->joints, jc, 1, rot, pos, g);
        float lowest = INFINITY, top = -INFINITY;
        for (int j = 1; j < jc; ++j) { /* joint 0 is the simulation bone, on the ground */
            lowest = fminf(lowest, g[j].translation.y);
            top = fmaxf(top, g[j].translation.y);
        }
        if (head > 0 && head < jc) top = g[head].translation.y;
        if (isfinite(top - lowest)) v[count++] = top - lowest;
    }
    return count > 0 ? mm__quantile(v, count, MM_POSTURE_REFERENCE_QUANTILE) / MM_POSTURE_HEAD_TO_STATURE
                     : 0.0f;
}

static void distance_counts(const mm_database *db, mm_diagnosis *d)
{
    for (int c = 0; c < db->clip_count; ++c) {
        mm_distance_curve curve;
        if (db->clips[c].type == MM_CLIP_IDLE || mm_database_distance_curve(db, c, &curve) != MM_OK) continue;
        for (int s = 0; s < curve.segment_count; ++s) d->stops += curve.segments[s].kind == MM_DISTANCE_STOP;
        float first_speed = (curve.travelled[1] - curve.travelled[0]) * curve.fps;
        d->starts += !curve.loop && first_speed < db->distance_clips[c].stop_speed;
    }
}

/* What each role is for, and what goes wrong without it. */
static const char *const role_names[MM_ROLE_COUNT] = {"hips",      "left_foot", "right_foot", "left_toe",
                                                      "right_toe", "left_hand", "right_hand", "head"};
static const char *role_use(int k)
{
    switch (k) {
    case MM_ROLE_HIPS:
        return "the build did not judge postures (T poses and lying stay in) and the metrics cannot judge "
               "the "
               "character's posture";
    case MM_ROLE_LEFT_FOOT:
    case MM_ROLE_RIGHT_FOOT:
        return "that foot has no heel contacts, and foot locking and IK leave it free: it may slide";
    case MM_ROLE_LEFT_TOE:
    case MM_ROLE_RIGHT_TOE:
        return "that foot has no toe contacts: foot locking holds the heel only";
    case MM_ROLE_LEFT_HAND:
    case MM_ROLE_RIGHT_HAND:
        return "moves that plant a hand (vaults, climbs) have no hand to place, and the build found no "
               "calibration pose";
    default:
        return "the build did not judge postures (T poses and lying stay in) and the metrics cannot measure "
               "the "
               "head's height";
    }
}

mm_result mm_database_diagnose(const mm_database *db, const mm_db_build_report *report, const mm_allocator *a,
                               mm_diagnosis *out)
{
    if (!db || !out) return MM_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    runtime_speeds(db, out->speeds);
    size_t scratch = db->frame_count > 0 ? (size_t)db->frame_count : 1;
    float *v = (float *)mm_alloc_array(a, scratch, sizeof(float));
    mm_xform *g =
        (mm_xform *)mm_alloc_array(a, db->joint_count > 0 ? (size_t)db->joint_count : 1, sizeof(mm_xform));
    if (!v || !g) {
        mm_free(a, v);
        mm_free(a, g);
        return MM_ERR_OUT_OF_MEMORY;
    }
    if (db->frame_count > 0 && db->root_velocity) cover_speeds(db, v, out->speeds);
    mm_result measured = envelopes(db, a, out);
    if (db->frame_count > 0 && db->joint_count > 1) out->height = standing_height(db, v, g);
    mm_free(a, v);
    mm_free(a, g);
    if (measured != MM_OK) return measured;
    int made = -1, poses = 0; /* the first standing clip the build made; those not mirrored */
    for (int c = 0; c < db->clip_count; ++c) {
        if (db->clips[c].type != MM_CLIP_IDLE) continue;
        ++out->idle_clips;
        if (strncmp(db->clips[c].name, MM__STANDING_PREFIX, strlen(MM__STANDING_PREFIX)) == 0) {
            ++out->standing_clips;
            poses += !db->clips[c].mirrored;
            if (made < 0) made = c;
        }
    }
    distance_counts(db, out);

    const mm_db_standing_report *st = report ? &report->standing : NULL;
    if (out->idle_clips && out->idle_clips == out->standing_clips) {
        char from[160] = "";
        if (st && st->status == MM_STANDING_MADE)
            snprintf(from, sizeof from, " (clip %s's frame %d, %.2f s)", st->from_clip, st->from_frame,
                     st->from_time);
        add(out, MM_DIAG_NO_IDLE,
            "no idle clip in the config: the build made %d standing pose%s from the takes, "
            "held with the feet planted (standing.make), the stillest %s%s, so stops stand "
            "still but do not breathe or shift: add an idle clip (a take of standing, "
            "\"type\": \"idle\"; mm bvh spans finds the standing spans of a take)",
            poses, poses == 1 ? "" : "s", db->clips[made].name, from);
    } else if (!out->idle_clips)
        add(out, MM_DIAG_NO_IDLE,
            "no idle clip: stops will slide (the character has nothing to stand still on)%s: add an idle "
            "clip (a take of standing, \"type\": \"idle\"; mm bvh spans finds the standing spans of a take)",
            st && st->status == MM_STANDING_OFF ? " and standing.make is false"
            : st && st->status == MM_STANDING_NOT_FOUND
                ? " and no locomotion frame is upright with both feet down to make a standing pose from"
                : "");
    for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
        const mm_speed_coverage *c = &out->speeds[k];
        if (c->covered) continue;
        const char *gait = mm_gait_name((mm_gait)c->gait), *dir = direction_names[c->direction],
                   *way = c->direction == 1 ? "sideways" : dir;
        char data[128];
        if (c->frames)
            snprintf(data, sizeof data, "%s it moves at %.2f-%.2f m/s (p10-p90 of %d frames)", way, c->p10,
                     c->p90, c->frames);
        else
            snprintf(data, sizeof data, "it has no frame moving %s", way);
        add(out, MM_DIAG_SPEED_NOT_COVERED,
            "%s %s at %.2f m/s (%s) is not covered: the locomotion the %s gait plays has %.1f s moving %s at "
            "%.2f-%.2f m/s (%s): the feet will slide; add clips that %s %s at about %.2f m/s, or set "
            "runtime.%s.%s_speed to a speed the data has",
            gait, dir, c->speed,
            c->from_settings ? "the database's runtime settings" : "the runtime's default", gait,
            (double)((float)c->near * db->interval), way, c->speed / MM_DIAGNOSE_SPEED_BAND,
            c->speed * MM_DIAGNOSE_SPEED_BAND, data, gait, way, c->speed, gait, dir);
    }
    if (!out->stops)
        add(out, MM_DIAG_NO_STOPS,
            "no clip comes to a stop (the distance curves hold no stop; mm db info's \"distance:\" line): a "
            "character told to stop will slide or pop into standing: add takes that walk and run to a stop");
    if (!out->starts)
        add(out, MM_DIAG_NO_STARTS,
            "no clip starts from rest (a one-shot clip whose root starts still): a character told to go "
            "from standing will slide into its first steps: add takes that start walking and running from "
            "standing");
    for (int k = 0; db->settings && k < MM_ROLE_COUNT; ++k)
        if (db->settings->roles[k] < 0)
            add(out, MM_DIAG_ROLE_MISSING,
                "roles.%s names no joint of the database (the config leaves it empty): %s; set roles.%s "
                "in the config to the joint's name (mm bvh info lists them)",
                role_names[k], role_use(k), role_names[k]);
    if (out->height > 0 && (out->height < MM_DIAGNOSE_MIN_HEIGHT || out->height > MM_DIAGNOSE_MAX_HEIGHT))
        add(out, MM_DIAG_HEIGHT,
            "the character stands %.3g m tall (from its head's height): the units look wrong (a person is "
            "1-2.5 m): set the config's scale to what makes metres of the files (0.01 for centimetres, "
            "0.0254 for inches), or 0 to detect it",
            out->height);
    if (report) {
        const int *n = report->source_frames;
        int judged = 0;
        for (int p = 0; p < MM_POSTURE_COUNT; ++p) judged += n[p];
        if (judged > 0) {
            int left = n[MM_POSTURE_CALIBRATION] + n[MM_POSTURE_LYING] + n[MM_POSTURE_ARMS_SPREAD] +
                       n[MM_POSTURE_HAND_RAISED] + n[MM_POSTURE_KNEE_RAISED],
                tagged = n[MM_POSTURE_CROUCHED] + n[MM_POSTURE_BENT];
            out->posture_share[0] = (float)left / (float)judged;
            out->posture_share[1] = (float)tagged / (float)judged;
            if (out->posture_share[0] > MM_DIAGNOSE_POSTURE_SHARE)
                add(out, MM_DIAG_POSTURES_LEFT_OUT,
                    "postures left out %.0f%% of the locomotion and idle frames (calibration %d, lying %d, "
                    "arms spread %d, hand raised %d, knee raised %d of %d): check the head and hands roles "
                    "and the scale, "
                    "or leave those spans out of the clips (mm bvh spans), or set postures.detect to false",
                    100.0 * out->posture_share[0], n[MM_POSTURE_CALIBRATION], n[MM_POSTURE_LYING],
                    n[MM_POSTURE_ARMS_SPREAD], n[MM_POSTURE_HAND_RAISED], n[MM_POSTURE_KNEE_RAISED], judged);
            if (out->posture_share[1] > MM_DIAGNOSE_POSTURE_SHARE)
                add(out, MM_DIAG_POSTURES_TAGGED,
                    "postures tagged %.0f%% of the locomotion and idle frames Crouch (crouched %d, bent %d "
                    "of "
                    "%d): only an input asking for crouch plays them; if they are ordinary walking or "
                    "running, tag them Walk or Run in the config, or set postures.detect to false",
                    100.0 * out->posture_share[1], n[MM_POSTURE_CROUCHED], n[MM_POSTURE_BENT], judged);
        }
    }
    for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
        const mm_speed_coverage *c = &out->speeds[k];
        if (!(c->speed > c->envelope * MM_DIAGNOSE_ENVELOPE_MARGIN)) continue;
        const char *gait = mm_gait_name((mm_gait)c->gait), *dir = direction_names[c->direction],
                   *way = c->direction == 1 ? "sideways" : dir;
        add(out, MM_DIAG_SPEED_ENVELOPE,
            "%s %s at %.2f m/s (%s) is above what the data covers %s, %.2f m/s (the speed envelope: the "
            "fastest %.1f s of the frames the gait plays within %.0f degrees of that way): %s; add clips "
            "that %s %s at about %.2f m/s, or set runtime.%s.%s_speed to at most %.2f",
            gait, dir, c->speed,
            c->from_settings ? "the database's runtime settings" : "the runtime's default", way, c->envelope,
            (double)MM_SPEED_ENVELOPE_COVER_SECONDS, (double)(MM_SPEED_ENVELOPE_WINDOW * 180.0 / MM_PI),
            out->bounded ? "the runtime moves no faster there (runtime.speed_envelope)"
                         : "runtime.speed_envelope is false, so the feet will slide",
            gait, way, c->speed, gait, dir, c->envelope);
    }
    return MM_OK;
}
