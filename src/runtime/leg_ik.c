/* Two-bone leg IK on joint positions, in double. See mm/leg_ik.h and docs/distance.md, "Stride
 * warping". Nothing here allocates. */
#include <mm/leg_ik.h>

#include <math.h>
#include <string.h>

#include "runtime/leg_ik_private.h"

mm_result mm_leg_ik_solve(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole, float max_extension,
                          mm_leg_warp *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    if (!leg) {
        memset(out, 0, sizeof *out);
        out->thigh = out->shin = mm_quat_identity();
        return MM_ERR_INVALID_ARGUMENT;
    }
    leg_identity(leg, out);
    if (!finite_leg(leg) || !finite3(target) || !finite3(pole) || bad_extension(max_extension))
        return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_LEG_IK_MAX_EXTENSION_DEFAULT;
    dvec hip = dv(leg->hip), knee = dv(leg->knee), foot = dv(leg->foot), tg = dv(target);
    double l1 = dlen(dsub(knee, hip)), l2 = dlen(dsub(foot, knee)), now = dlen(dsub(foot, hip));
    if (l1 < 1e-6 || l2 < 1e-6) return MM_ERR_INVALID_ARGUMENT;
    double rmax = leg_reach(l1, l2, now, ext), rmin = fabs(l1 - l2);
    if (now < rmin) rmin = now;
    dvec d = dsub(tg, hip);
    double len = dlen(d);
    dvec u;
    if (len > 1e-9)
        u = dscale(d, 1.0 / len);
    else if (now > 1e-9)
        u = dscale(dsub(foot, hip), 1.0 / now);
    else
        u = (dvec){0.0, -1.0, 0.0};
    len = clampd(len, rmin, rmax);
    /* the knee: the animated leg swung rigidly onto the new hip-target axis (the smallest turn),
     * so that the knee keeps its side however close the new axis passes to it (the knee's side of
     * that axis flipped from one tick to the next: knee pops of 20 cm); where the leg must bend
     * more than it does, the extra bend goes to the pole's side. A nearly straight leg's own
     * plane is noise that flips as the animated leg passes straight (the knee jumped 19 cm in
     * one tick on the built-in set's demo), so it only carries the bend the animation has. A
     * target at the foot leaves the leg as it is, unless it is nearly straight and bent against
     * the pole. */
    dvec kh = dsub(knee, hip), fh = dsub(foot, hip);
    dvec swung = dv(mm_quat_rotate(mm_quat_between(fv(fh), fv(u)), fv(kh)));
    dvec n = dsub(swung, dscale(u, ddot(swung, u))), p = dv(pole);
    p = dsub(p, dscale(u, ddot(p, u)));
    double pl = dlen(p);
    if (pl > 1e-9 && now > 1e-9) {
        /* a bend against the pole is the animation's only while the leg is clearly bent; as it
         * straightens that part fades (fully dropped from a sine of 0 between thigh and hip-foot
         * line, kept from 0.1, about 6 degrees) */
        double back = ddot(n, p) / pl, bent = dlen(dcross(kh, fh)) / (l1 * now);
        if (back < 0.0) n = dsub(n, dscale(p, back / pl * clampd(1.0 - bent / 0.1, 0.0, 1.0)));
    }
    double have = dlen(n);
    double a = len > 1e-12 ? (l1 * l1 - l2 * l2 + len * len) / (2.0 * len) : 0.0;
    double h2 = l1 * l1 - a * a, h = h2 > 0.0 ? sqrt(h2) : 0.0;
    if (pl > 1e-9 && h > have) n = dadd(n, dscale(p, (h - have) / pl));
    if (dlen(n) < 1e-9 * l1) {
        dvec axis = fabs(u.x) < 0.9 ? (dvec){1.0, 0.0, 0.0} : (dvec){0.0, 0.0, 1.0};
        n = dsub(axis, dscale(u, ddot(axis, u)));
    }
    n = dscale(n, 1.0 / dlen(n));
    dvec knee1 = dadd(hip, dadd(dscale(u, a), dscale(n, h))), foot1 = dadd(hip, dscale(u, len));
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
