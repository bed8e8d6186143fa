/* Bone roles: the default joint name of each role (the one table of them: mm_config_defaults
 * writes them into a config, and the runtime falls back on them for a database without roles),
 * and the joint of a role in a database. */
#include <mm/database.h>

#include <string.h>

const char *mm_role_default_name(mm_role role)
{
    static const char *const names[MM_ROLE_COUNT] = {"Hips",     "LeftFoot", "RightFoot", "LeftToe",
                                                     "RightToe", "LeftHand", "RightHand", "Head"};
    return (int)role >= 0 && role < MM_ROLE_COUNT ? names[role] : NULL;
}

int mm_database_find_joint(const mm_database *db, const char *name)
{
    int found = -1;
    for (int j = 0; db && name && j < db->joint_count; ++j)
        if (strcmp(db->joints[j].name, name) == 0) found = j;
    return found;
}

int mm_database_role_joint(const mm_database *db, mm_role role)
{
    if (!db || (int)role < 0 || role >= MM_ROLE_COUNT) return -1;
    if (db->settings) return db->settings->roles[role]; /* the loader checked it: -1 or a joint */
    return mm_database_find_joint(db, mm_role_default_name(role));
}

int mm_database_toe_joint(const mm_database *db, int ankle, mm_role toe_role)
{
    if (!db || ankle < 0 || ankle >= db->joint_count) return -1;
    int toe = mm_database_role_joint(db, toe_role);
    if (toe >= 0 && db->joints[toe].parent == ankle) return toe;
    for (int j = ankle + 1; j < db->joint_count; ++j)
        if (db->joints[j].parent == ankle) return j;
    return -1;
}
