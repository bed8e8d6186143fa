/* Gait names. See mm/gait.h. */
#include <mm/gait.h>

#include <string.h>

static const char *gait_names[MM_GAIT_COUNT] = {"walk", "run", "crouch", "jump"};

const char *mm_gait_name(mm_gait g) { return (int)g >= 0 && g < MM_GAIT_COUNT ? gait_names[g] : NULL; }

mm_gait mm_gait_parse(const char *name)
{
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        if (name && strcmp(name, gait_names[g]) == 0) return (mm_gait)g;
    return MM_GAIT_COUNT;
}
