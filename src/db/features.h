/* features.h (private) - raw feature rows of one processed clip. */
#ifndef MM_DB_FEATURES_H
#define MM_DB_FEATURES_H

#include <mm/database_build.h>

/* Lays out the feature groups for a config and skeleton (joint 0 the simulation root). Fills
 * groups (at most MM_MAX_MATCH_BONES * 2 + 1 + 2 * MM_MAX_TRAJ_SAMPLES) and returns the count,
 * or -1 with err set when a bone is missing. *dims receives the total. */
int mm__feature_layout(const mm_config *cfg, const mm_skeleton *s, mm_feature_group *groups, int *dims,
                       mm_error *err);

/* Raw features of every frame of clip (rows of stride floats) from its global transforms
 * ([frames x joints]) and root motion. Trajectory samples beyond the clip follow seed 000:
 * before the start, the first frame's velocity and facing; after the end, the next cycles of
 * a loop (accumulating the cycle's displacement and turn), otherwise the last frame's velocity
 * and facing. */
void mm__clip_features(const mm_clip *clip, int loop, const mm_xform *globals, const mm_vec3 *root_velocity,
                       const mm_feature_group *groups, int group_count, float interval, float *out,
                       int stride);

#endif
