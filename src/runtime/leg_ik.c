/* Two-bone leg IK on joint positions, in double. See mm/leg_ik.h and docs/distance.md, "Stride
 * warping". Nothing here allocates. */
#include <mm/leg_ik.h>

#include <math.h>
#include <string.h>

#include "runtime/leg_ik_private.h"

/* The hip-to-foot distance asked for a target at distance len, softened within the last
 * `soft` share of the leg's length (see mm_leg_ik_params.soft_reach). */
static double soften(double len, double length, double soft)
{
    double s = soft * length, start = length - s;
    if (!(len > start) || !(s > 0.0)) return len;
    return length - s * exp(-(len - start) / s);
}

/* sine of the knee's bend (seen from the hip) from which the animated knee's side is trusted fully:
 * a nearly straight leg's side is noise that flips as the leg passes straight */
#define BEND_SIDE_TRUST 0.2
/* cosine between the animated knee's side and the pole's from which that side is trusted fully (60
 * degrees: knees turn out that far; trust fades to none at 90) */
#define SIDE_TOWARD_POLE 0.5
/* sine between the pole and the hip-foot line under which the pole says less and less about the
 * side (a leg thrown sideways in a jump, along the pelvis's facing): the animated side is kept */
#define POLE_ALONG_LEG 0.3

/* v turned about the unit axis k by angle (Rodrigues). */
static dvec turn(dvec v, dvec k, double angle)
{
    double c = cos(angle), s = sin(angle);
    return dadd(dadd(dscale(v, c), dscale(dcross(k, v), s)), dscale(k, ddot(k, v) * (1.0 - c)));
}

/* v turned by the smallest rotation that takes the unit vector from onto the unit vector to (v
 * itself when they are opposite). */
static dvec swing(dvec v, dvec from, dvec to)
{
    dvec k = dcross(from, to);
    double sine = dlen(k);
    return sine < 1e-12 ? v : turn(v, dscale(k, 1.0 / sine), atan2(sine, ddot(from, to)));
}

/* The unit part of v square to the unit vector u; zero when v is (nearly) along u. */
static dvec square_to(dvec v, dvec u)
{
    dvec p = dsub(v, dscale(u, ddot(v, u)));
    double l = dlen(p);
    return l > 1e-9 ? dscale(p, 1.0 / l) : (dvec){0.0, 0.0, 0.0};
}

/* The side the knee bends to, square to the hip-foot direction ac: the animated knee's own side
 * (own, unit, with the sine of its bend `bent`) as far as the leg is clearly bent and that side is
 * within 60 degrees of the pole, or the pole lies nearly along the leg and says little about a side
 * (a leg thrown sideways in a jump); the pole's side otherwise (a knee the animation hyperextends
 * is bent forward); turned from the one toward the other about ac in between. It depends on the
 * animation and the pole alone, never on how far the leg must bend (a side that did flipped as the
 * bend asked for passed the animated one: docs/distance.md, "One leg IK"). */
static dvec knee_side(dvec ac, dvec own, double bent, dvec pole)
{
    double pl = dlen(pole);
    dvec p = square_to(pole, ac);
    if (ddot(p, p) == 0.0) { /* no pole: the knee's own side, or any */
        if (ddot(own, own) > 0.0) return own;
        return square_to(fabs(ac.x) < 0.9 ? (dvec){1.0, 0.0, 0.0} : (dvec){0.0, 0.0, 1.0}, ac);
    }
    if (ddot(own, own) == 0.0) return p;
    double cosine = ddot(p, own),
           along = 1.0 - clampd(dlen(dcross(pole, ac)) / (pl * POLE_ALONG_LEG), 0.0, 1.0);
    double toward = clampd(cosine / SIDE_TOWARD_POLE, 0.0, 1.0);
    double w = clampd(bent / BEND_SIDE_TRUST, 0.0, 1.0) * (toward + (1.0 - toward) * along);
    return w == 0.0 ? p : turn(p, ac, w * atan2(ddot(dcross(p, own), ac), cosine));
}

mm_result mm_leg_ik_solve(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole,
                          const mm_leg_ik_params *params, mm_leg_warp *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    if (!leg) {
        memset(out, 0, sizeof *out);
        out->thigh = out->shin = mm_quat_identity();
        return MM_ERR_INVALID_ARGUMENT;
    }
    leg_identity(leg, out);
    float max_extension = params ? params->max_extension : 0.0f, soft = params ? params->soft_reach : 0.0f;
    if (!finite_leg(leg) || !finite3(target) || !finite3(pole) || bad_extension(max_extension) ||
        !(soft >= 0.0f && soft <= 0.5f))
        return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_LEG_IK_MAX_EXTENSION_DEFAULT;
    dvec hip = dv(leg->hip), knee = dv(leg->knee), foot = dv(leg->foot), tg = dv(target);
    double l1 = dlen(dsub(knee, hip)), l2 = dlen(dsub(foot, knee)), now = dlen(dsub(foot, hip));
    if (!leg_solvable(l1, l2, now)) return MM_ERR_INVALID_ARGUMENT;
    double rmax = leg_reach(l1, l2, now, ext), rmin = fabs(l1 - l2);
    if (now < rmin) rmin = now;
    dvec d = dsub(tg, hip), ac = dscale(dsub(foot, hip), 1.0 / now);
    double dl = dlen(d);
    dvec u = dl > 1e-9 ? dscale(d, 1.0 / dl) : ac;
    double len = clampd(soften(dl, l1 + l2, soft), rmin, rmax);
    /* the side the knee bends to, swung with the leg onto the new hip-target axis */
    dvec kh = dsub(knee, hip);
    double bent = dlen(dcross(kh, ac)) / l1;
    dvec side = square_to(swing(knee_side(ac, square_to(kh, ac), bent, dv(pole)), ac, u), u);
    if (ddot(side, side) == 0.0) side = knee_side(u, (dvec){0.0, 0.0, 0.0}, 0.0, dv(pole));
    /* the knee where thigh and shin meet over the hip-target distance */
    double a = (l1 * l1 - l2 * l2 + len * len) / (2.0 * len), h2 = l1 * l1 - a * a,
           h = h2 > 0.0 ? sqrt(h2) : 0.0;
    dvec knee1 = dadd(hip, dadd(dscale(u, a), dscale(side, h))), foot1 = dadd(hip, dscale(u, len));
    out->pose.knee = fv(knee1);
    out->pose.foot = fv(foot1);
    out->target = target;
    out->thigh = mm_quat_between(fv(kh), fv(dsub(knee1, hip)));
    mm_vec3 shin0 = mm_quat_rotate(out->thigh, fv(dsub(foot, knee)));
    out->shin = mm_quat_normalize(mm_quat_mul(mm_quat_between(shin0, fv(dsub(foot1, knee1))), out->thigh));
    if (!finite_leg(&out->pose) || !isfinite(out->thigh.w + out->thigh.x + out->thigh.y + out->thigh.z) ||
        !isfinite(out->shin.w + out->shin.x + out->shin.y + out->shin.z)) {
        leg_identity(leg, out); /* numbers too large for floats */
        return MM_ERR_OUT_OF_RANGE;
    }
    return MM_OK;
}
