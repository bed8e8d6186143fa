/* The character's rig: legs, pelvis and spine found by name and parentage. */
#include "rig.h"

#include <string.h>

static int find_joint(const mm_joint *joints, int joint_count, const char *name)
{
    int found = -1;
    for (int j = 0; j < joint_count; ++j)
        if (strcmp(joints[j].name, name) == 0) found = j;
    return found;
}

void mm_rig_init(mm_rig *rig, const mm_joint *joints, int joint_count, const char *left_foot,
                 const char *right_foot)
{
    memset(rig, 0, sizeof *rig);
    rig->joints = joints;
    rig->joint_count = joint_count;
    const char *names[2] = {left_foot ? left_foot : "LeftFoot", right_foot ? right_foot : "RightFoot"};
    rig->pelvis = -1;
    for (int k = 0; k < 2; ++k) {
        int ankle = find_joint(joints, joint_count, names[k]);
        /* the chain ankle <- knee <- hip must exist below the root */
        if (ankle >= 0 && (joints[ankle].parent < 1 || joints[joints[ankle].parent].parent < 1)) ankle = -1;
        rig->ankle[k] = ankle;
        rig->knee[k] = ankle >= 0 ? joints[ankle].parent : -1;
        rig->hip[k] = ankle >= 0 ? joints[rig->knee[k]].parent : -1;
        rig->toe[k] = -1;
        for (int j = ankle + 1; ankle >= 0 && j < joint_count && rig->toe[k] < 0; ++j)
            if (joints[j].parent == ankle) rig->toe[k] = j;
    }
    if (rig->ankle[0] >= 0 && rig->ankle[1] >= 0) {
        int left = joints[rig->hip[0]].parent, right = joints[rig->hip[1]].parent;
        if (left == right && left >= 1) rig->pelvis = left;
    }
    int pelvis = rig->pelvis;
    for (int j = pelvis + 1; pelvis >= 0 && j < joint_count && rig->spine_count == 0; ++j) {
        if (joints[j].parent != pelvis) continue;
        int leg = 0;
        for (int k = 0; k < 2; ++k)
            for (int a = rig->ankle[k]; a > pelvis; a = joints[a].parent) leg |= a == j;
        if (leg) continue;
        for (int at = j; at >= 0 && rig->spine_count < MM_RIG_MAX_SPINE;) {
            rig->spine[rig->spine_count++] = at;
            int child = -1, children = 0;
            for (int k = at + 1; k < joint_count; ++k)
                if (joints[k].parent == at) child = children++ ? child : k;
            at = children == 1 ? child : -1;
        }
    }
}

void mm_rig_forward(const mm_rig *rig, int first, mm_rig_pose *pose)
{
    mm_skeleton_global_from(rig->joints, rig->joint_count, first, pose->local_rotations,
                            pose->local_positions, pose->global);
}
