/* skeleton_variants.c - takes rewritten for the tests (skeleton_variants.h). */
#define _POSIX_C_SOURCE 200809L
#include "skeleton_variants.h"

#include <ctype.h>
#include <math.h>

#include <mm/bvh.h>
#include <mm/import.h>

#include "test_util.h"

const char *const sv_naming_names[SV_NAMINGS] = {"Left/Right", "_L/_R", "l_/r_",    "L/R",
                                                 "Mixamo",     "CMU",   "Biovision"};
const char *const sv_root_names[SV_ROOTS_ALL] = {"static root", "part root",   "all root", "ground root",
                                                 "yaw root",    "placed root", "two roots"};
const char *const sv_axis_names[4] = {"+X", "-X", "+Z", "-Z"};

/* ---- names --------------------------------------------------------------------------------- */

int sv_name_side(const char *name, const char **part)
{
    int side = 0;
    size_t skip = 0;
    if (strncmp(name, "Left", 4) == 0 && isupper((unsigned char)name[4]))
        side = 1, skip = 4;
    else if (strncmp(name, "Right", 5) == 0 && isupper((unsigned char)name[5]))
        side = 2, skip = 5;
    else if (strchr("lLrR", name[0]) && name[0] && isupper((unsigned char)name[1]))
        side = name[0] == 'l' || name[0] == 'L' ? 1 : 2, skip = 1;
    *part = name + skip;
    return side;
}

/* Limb parts: the UpLeg style (LAFAN1, Mixamo, CMU, the built-in set) and the Hip style
 * (Biovision, games105). */
enum { THIGH, SHIN, FOOT, TOE, CLAVICLE, UPPER_ARM, FOREARM, HAND, PARTS };
static const char *const upleg_style[PARTS] = {"UpLeg",    "Leg", "Foot",    "Toe",
                                               "Shoulder", "Arm", "ForeArm", "Hand"};
static const char *const hip_style[PARTS] = {"Hip",    "Knee",     "Ankle", "Toe",
                                             "Collar", "Shoulder", "Elbow", "Wrist"};

/* Which limb part a name's part is in the skeleton's style; -1 for none. */
static int limb_part(const char *part, int hip_styled)
{
    if (strcmp(part, "ToeBase") == 0 || strcmp(part, "ToeJoint") == 0) return TOE;
    if (hip_styled && (strcmp(part, "Torso_Clavicle") == 0 || strcmp(part, "Clavicle") == 0)) return CLAVICLE;
    const char *const *table = hip_styled ? hip_style : upleg_style;
    for (int i = 0; i < PARTS; ++i)
        if (strcmp(part, table[i]) == 0) return i;
    return -1;
}

/* Whether the skeleton names its limbs Hip / Knee / Ankle (no *UpLeg joint). */
static int hip_styled(const mm_skeleton *s)
{
    for (int j = 0; j < s->joint_count; ++j) {
        const char *part;
        if (sv_name_side(s->joints[j].name, &part) && strcmp(part, "UpLeg") == 0) return 0;
    }
    return 1;
}

void sv_rename_joint(const mm_skeleton *skel, int joint, sv_naming n, char out[MM_NAME_MAX])
{
    const char *name = skel->joints[joint].name, *part;
    int side = sv_name_side(name, &part);
    int limb = side ? limb_part(part, hip_styled(skel)) : -1;
    char low[MM_NAME_MAX];
    size_t k = 0;
    for (; part[k] && k + 1 < MM_NAME_MAX; ++k) low[k] = (char)tolower((unsigned char)part[k]);
    low[k] = 0;
    static const char *const words[3] = {"", "Left", "Right"}, *const letters[3] = {"", "L", "R"},
                             *const small[3] = {"", "l", "r"};
    if (!side) { /* a joint of no side keeps its name (Mixamo prefixes it) */
        snprintf(out, MM_NAME_MAX, "%s%.50s", n == SV_NAMES_MIXAMO ? "mixamorig:" : "", name);
        return;
    }
    switch (n) {
    case SV_NAMES_LEFT_RIGHT:
        snprintf(out, MM_NAME_MAX, "%s%.55s", words[side], part);
        break;
    case SV_NAMES_SUFFIX_LR:
        snprintf(out, MM_NAME_MAX, "%.60s_%s", part, letters[side]);
        break;
    case SV_NAMES_PREFIX_L_:
        snprintf(out, MM_NAME_MAX, "%s_%.60s", small[side], low);
        break;
    case SV_NAMES_PREFIX_L:
        snprintf(out, MM_NAME_MAX, "%s%.60s", letters[side], part);
        break;
    case SV_NAMES_MIXAMO:
    case SV_NAMES_CMU:
        snprintf(out, MM_NAME_MAX, "%s%s%.45s", n == SV_NAMES_MIXAMO ? "mixamorig:" : "", words[side],
                 limb == TOE ? "ToeBase"
                 : limb >= 0 ? upleg_style[limb]
                             : part);
        break;
    default: /* Biovision */
        snprintf(out, MM_NAME_MAX, "%s%.55s", words[side], limb >= 0 ? hip_style[limb] : part);
        break;
    }
}

/* ---- generators ---------------------------------------------------------------------------- */

static void identity_origin(sv_variant *v)
{
    assert_true(v->clip.skeleton.joint_count <= SV_MAX_JOINTS);
    for (int j = 0; j < v->clip.skeleton.joint_count; ++j) v->origin[j] = j;
}

void sv_copy(const mm_clip *src, sv_variant *out)
{
    memset(out, 0, sizeof *out);
    assert_int_equal(mm_clip_copy(&out->clip, src, NULL), MM_OK);
    out->unit = 1.0;
    identity_origin(out);
}

void sv_rename(const mm_clip *src, sv_naming n, sv_variant *out)
{
    sv_copy(src, out);
    mm_skeleton *s = &out->clip.skeleton;
    for (int j = 0; j < s->joint_count; ++j) sv_rename_joint(&src->skeleton, j, n, s->joints[j].name);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_skeleton_validate(s, &err) != MM_OK) fail_msg("%s names: %s", sv_naming_names[n], err.message);
}

static mm_quat yaw(float angle) { return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), angle); }

/* The world transform of the joint above the hips at frame f, given the hips' world. */
static mm_xform carrier(sv_root a, mm_xform hips, int f)
{
    mm_vec3 t = hips.translation, ground = mm_vec3_make(t.x, 0.0f, t.z);
    mm_vec3 z = mm_quat_rotate(hips.rotation, mm_vec3_make(0, 0, 1));
    float heading = atan2f(z.x, z.z);
    switch (a) {
    case SV_ROOT_PART:
        return mm_xform_make(mm_quat_identity(), mm_vec3_make(0.5f * t.x, 0.0f, 0.5f * t.z));
    case SV_ROOT_ALL:
        return mm_xform_make(mm_quat_identity(), t);
    case SV_ROOT_GROUND:
        return mm_xform_make(mm_quat_identity(), ground);
    case SV_ROOT_YAW:
        return mm_xform_make(yaw(heading + 0.3f * sinf(0.05f * (float)f)), ground);
    case SV_ROOT_PLACED:
        return mm_xform_make(yaw(0.7f), mm_vec3_make(2.0f, 0.0f, -3.0f));
    case SV_ROOT_TWO: /* the Root under the Reference (at the origin, not turned) */
        return mm_xform_make(yaw(-heading + 0.2f * cosf(0.03f * (float)f)), ground);
    default:
        return mm_xform_identity();
    }
}

void sv_reroot_prop(const mm_clip *src, sv_root a, int prop, sv_variant *out)
{
    memset(out, 0, sizeof *out);
    out->unit = 1.0;
    const mm_skeleton *s = &src->skeleton;
    int tops = a == SV_ROOT_TWO ? 2 : 1, jc = s->joint_count, n = tops + jc + (prop != 0);
    int moving = a != SV_ROOT_STATIC && a != SV_ROOT_PLACED;
    assert_true(n <= SV_MAX_JOINTS);
    mm_skeleton ns;
    assert_int_equal(mm_skeleton_init(&ns, n, NULL), MM_OK);
    snprintf(ns.joints[0].name, MM_NAME_MAX, "%s", tops == 2 ? "Reference" : "Root");
    ns.joints[0].parent = -1;
    ns.joints[0].order = MM_EULER_ZYX;
    out->origin[0] = -1;
    if (tops == 2) {
        snprintf(ns.joints[1].name, MM_NAME_MAX, "Root");
        ns.joints[1].parent = 0;
        ns.joints[1].order = MM_EULER_ZYX;
        out->origin[1] = -1;
    }
    ns.joints[tops - 1].flags = moving ? MM_JOINT_TRANSLATES : 0;
    if (a == SV_ROOT_PLACED) ns.joints[0].offset = mm_vec3_make(2.0f, 0.0f, -3.0f);
    for (int j = 0; j < jc; ++j) {
        ns.joints[tops + j] = s->joints[j];
        ns.joints[tops + j].parent = s->joints[j].parent < 0 ? tops - 1 : s->joints[j].parent + tops;
        out->origin[tops + j] = j;
    }
    ns.joints[tops].flags |= MM_JOINT_TRANSLATES;
    if (prop) {
        snprintf(ns.joints[n - 1].name, MM_NAME_MAX, "Prop");
        ns.joints[n - 1].parent = tops - 1;
        ns.joints[n - 1].offset = mm_vec3_make(0.0f, 0.1f, 0.0f);
        ns.joints[n - 1].order = MM_EULER_ZYX;
        out->origin[n - 1] = -1;
    }
    assert_int_equal(mm_clip_init(&out->clip, &ns, src->frame_count, src->fps, NULL), MM_OK);
    mm_skeleton_free(&ns);
    for (int f = 0; f < src->frame_count; ++f) {
        const mm_quat *sr = mm_clip_rotations(src, f);
        const mm_vec3 *sp = mm_clip_positions(src, f);
        mm_quat *r = mm_clip_rotations(&out->clip, f);
        mm_vec3 *p = mm_clip_positions(&out->clip, f);
        mm_xform hips = mm_xform_make(sr[0], sp[0]), top = carrier(a, hips, f);
        mm_xform local = mm_xform_mul(mm_xform_inverse(top), hips);
        r[tops - 1] = top.rotation;
        p[tops - 1] = top.translation;
        memcpy(r + tops, sr, sizeof(mm_quat) * (size_t)jc);
        memcpy(p + tops, sp, sizeof(mm_vec3) * (size_t)jc);
        r[tops] = local.rotation;
        p[tops] = local.translation;
    }
}

void sv_reroot(const mm_clip *src, sv_root a, sv_variant *out) { sv_reroot_prop(src, a, 0, out); }

void sv_turn_rest_frames(const mm_clip *src, mm_quat turn, const char *prefix, sv_variant *out)
{
    sv_copy(src, out);
    mm_skeleton *s = &out->clip.skeleton;
    int jc = s->joint_count;
    mm_quat turns[SV_MAX_JOINTS];
    for (int j = 0; j < jc; ++j)
        turns[j] =
            !prefix || strncmp(s->joints[j].name, prefix, strlen(prefix)) == 0 ? turn : mm_quat_identity();
    for (int j = 0; j < jc; ++j) {
        int p = s->joints[j].parent;
        if (p >= 0) s->joints[j].offset = mm_quat_rotate(mm_quat_conj(turns[p]), s->joints[j].offset);
        s->joints[j].end_site = mm_quat_rotate(mm_quat_conj(turns[j]), s->joints[j].end_site);
    }
    for (int f = 0; f < out->clip.frame_count; ++f) {
        mm_quat *r = mm_clip_rotations(&out->clip, f);
        mm_vec3 *pos = mm_clip_positions(&out->clip, f);
        for (int j = 0; j < jc; ++j) {
            int p = s->joints[j].parent;
            mm_quat before = p >= 0 ? mm_quat_conj(turns[p]) : mm_quat_identity();
            r[j] = mm_quat_normalize(mm_quat_mul(before, mm_quat_mul(r[j], turns[j])));
            if (p >= 0) pos[j] = mm_quat_rotate(before, pos[j]);
        }
    }
}

void sv_rest_axes(const mm_clip *src, int axis, sv_variant *out)
{
    /* turn: the rotation whose inverse takes +Y to the axis (offsets become turn^-1 o) */
    static const float angles[4] = {(float)(MM_PI / 2), (float)(-MM_PI / 2), (float)(-MM_PI / 2),
                                    (float)(MM_PI / 2)};
    mm_vec3 about = axis < 2 ? mm_vec3_make(0, 0, 1) : mm_vec3_make(1, 0, 0);
    mm_quat turn = mm_quat_from_axis_angle(about, angles[axis]);
    static const float want[4][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    mm_vec3 y = mm_quat_inv_rotate(turn, mm_vec3_make(0, 1, 0));
    assert_true(fabsf(y.x - want[axis][0]) + fabsf(y.y) + fabsf(y.z - want[axis][2]) < 1e-6f);
    sv_turn_rest_frames(src, turn, NULL, out);
}

void sv_units(const mm_clip *src, double unit, sv_variant *out)
{
    sv_copy(src, out);
    mm_clip_scale(&out->clip, (float)(1.0 / unit));
    out->unit = unit;
}

void sv_rotation_order(const mm_clip *src, mm_euler_order order, sv_variant *out)
{
    sv_copy(src, out);
    out->order = order;
}

void sv_resample(const mm_clip *src, float fps, sv_variant *out)
{
    memset(out, 0, sizeof *out);
    assert_int_equal(mm_clip_resample_interp(&out->clip, src, fps, MM_INTERP_CUBIC, NULL), MM_OK);
    out->unit = 1.0;
    identity_origin(out);
}

void sv_free(sv_variant *v) { mm_clip_free(&v->clip); }

/* ---- checks -------------------------------------------------------------------------------- */

double sv_fk_distance(const mm_clip *orig, double orig_unit, const sv_variant *v)
{
    int jo = orig->skeleton.joint_count, jv = v->clip.skeleton.joint_count, compared = 0;
    mm_xform *a = malloc(sizeof(mm_xform) * (size_t)jo), *b = malloc(sizeof(mm_xform) * (size_t)jv);
    assert_true(a && b);
    double worst = 0.0;
    for (int f = 0; f < v->clip.frame_count; ++f) {
        double x = (double)f * (double)orig->fps / (double)v->clip.fps; /* the original's frame then */
        double k = floor(x + 0.5);
        if (fabs(x - k) > 1e-6 || k >= orig->frame_count) continue;
        mm_clip_fk(orig, (int)k, a);
        mm_clip_fk(&v->clip, f, b);
        ++compared;
        for (int j = 0; j < jv; ++j) {
            int o = v->origin[j];
            if (o < 0) continue;
            mm_vec3 p = a[o].translation, q = b[j].translation;
            double dx = p.x * orig_unit - q.x * v->unit, dy = p.y * orig_unit - q.y * v->unit,
                   dz = p.z * orig_unit - q.z * v->unit;
            worst = fmax(worst, sqrt(dx * dx + dy * dy + dz * dz));
            if (isnan(dx + dy + dz)) worst = INFINITY;
        }
    }
    free(a);
    free(b);
    return compared > 0 ? worst : INFINITY;
}

double sv_check(const mm_clip *orig, double orig_unit, const sv_variant *v, const char *what)
{
    double d = sv_fk_distance(orig, orig_unit, v);
    if (!(d <= SV_FK_TOLERANCE))
        fail_msg("variant %s: world joints %.3g m from the original's (at most %g): a generator bug", what, d,
                 SV_FK_TOLERANCE);
    return d;
}

void sv_save_and_reload(const mm_clip *orig, double orig_unit, sv_variant *v, const char *path)
{
    sv_check(orig, orig_unit, v, path); /* the generator */
    mm_error err;
    memset(&err, 0, sizeof err);
    char *text = NULL;
    size_t size = 0;
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    wd.order = v->order;
    if (mm_bvh_write(&v->clip, &wd, &text, &size, &err) != MM_OK) fail_msg("%s: %s", path, err.message);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, size, f), size);
    fclose(f);
    mm_free(NULL, text);
    mm_import_desc desc;
    memset(&desc, 0, sizeof desc);
    mm_clip_list list;
    if (mm_import_clips(path, &desc, &list, &err) != MM_OK) fail_msg("%s: %s", path, err.message);
    assert_int_equal(list.count, 1);
    /* the file lists the joints depth first: the origins follow the names */
    int origin[SV_MAX_JOINTS];
    const mm_skeleton *back = &list.clips[0].skeleton;
    assert_int_equal(back->joint_count, v->clip.skeleton.joint_count);
    for (int j = 0; j < back->joint_count; ++j) {
        int k = mm_skeleton_find(&v->clip.skeleton, back->joints[j].name);
        assert_true(k >= 0);
        origin[j] = v->origin[k];
    }
    memcpy(v->origin, origin, sizeof(int) * (size_t)back->joint_count);
    mm_clip_free(&v->clip);
    v->clip = list.clips[0];
    memset(&list.clips[0], 0, sizeof list.clips[0]);
    mm_clip_list_free(&list);
    sv_check(orig, orig_unit, v, path); /* the writer and the reader */
}
