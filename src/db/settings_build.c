/* The runtime settings a config gives a database: resolved into the settings section by the build
 * (mm__db_settings_resolve), which src/tuning/ also applies to a character desc directly
 * (mm_character_desc_apply_config, for tools that load a config at run time). The runtime reads
 * the section with mm_character_desc_from_database (src/runtime/character_settings.c): the two
 * give the same desc (tests/test_settings.c). */
#include "db/settings_build.h"

#include <string.h>

#include <mm/speed_envelope.h>

#include "db/db_file.h"

mm_result mm__db_settings_resolve(const mm_config *cfg, const mm_database *db, mm_database_settings *out,
                                  mm_error *err)
{
    memset(out, 0, sizeof *out);
    /* the feature weights, as mm_character_desc_apply_config takes them: per feature group of db */
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        if (grp->kind == MM_FEATURE_BONE_POSITION || grp->kind == MM_FEATURE_BONE_VELOCITY) {
            int slot = mm_database_matched_bone(db, g);
            const char *name =
                grp->bone >= 0 && grp->bone < db->joint_count ? db->joints[grp->bone].name : "";
            for (int b = 0; b < cfg->bone_count && slot >= 0; ++b) {
                if (strcmp(cfg->bones[b].name, name) != 0) continue;
                if (grp->kind == MM_FEATURE_BONE_POSITION && (cfg->bones[b].features & MM_MATCH_POSITION)) {
                    out->joint_position_weights[slot] = cfg->bones[b].position_weight;
                    out->position_set |= 1u << slot;
                }
                if (grp->kind == MM_FEATURE_BONE_VELOCITY && (cfg->bones[b].features & MM_MATCH_VELOCITY)) {
                    out->joint_velocity_weights[slot] = cfg->bones[b].velocity_weight;
                    out->velocity_set |= 1u << slot;
                }
                break;
            }
        } else if (grp->kind == MM_FEATURE_ROOT_VELOCITY) {
            out->body_velocity_weight = cfg->body_velocity_weight;
            out->weight_set |= MM_SETTINGS_BODY_VELOCITY_WEIGHT;
        } else if (grp->kind == MM_FEATURE_TRAJ_POSITION) {
            out->position_multiplier = cfg->position_multiplier;
            out->weight_set |= MM_SETTINGS_POSITION_MULTIPLIER;
        } else if (grp->kind == MM_FEATURE_TRAJ_DIRECTION) {
            out->angle_multiplier = cfg->angle_multiplier;
            out->weight_set |= MM_SETTINGS_ANGLE_MULTIPLIER;
        }
    }
    /* the runtime object: the fields set, and only those */
    const mm_runtime_config *rt = &cfg->runtime;
    out->set = rt->set & MM_RUNTIME_FIELDS_ALL;
    if (rt->set & MM_RUNTIME_POSE_TRAJECTORY_RATIO) out->pose_trajectory_ratio = rt->pose_trajectory_ratio;
    if (rt->set & MM_RUNTIME_NEXT_POSE_FAVOUR) out->next_pose_favour = rt->next_pose_favour;
    if (rt->set & MM_RUNTIME_LOOP_ANIM_FAVOUR) out->loop_anim_favour = rt->loop_anim_favour;
    if (rt->set & MM_RUNTIME_CONTINUING_BIAS) out->continuing_bias = rt->continuing_bias;
    if (rt->set & MM_RUNTIME_SEARCH_INTERVAL) out->search_interval = rt->search_interval;
    if (rt->set & MM_RUNTIME_TRANSITION_HALFLIFE) out->transition_halflife = rt->transition_halflife;
    if (rt->set & MM_RUNTIME_IDLE_SPEED) out->idle_speed = rt->idle_speed;
    if (rt->set & MM_RUNTIME_SYNC_HALFLIFE) out->sync_halflife = rt->sync_halflife;
    if (rt->set & MM_RUNTIME_DISTANCE_MATCHING) out->distance_matching = rt->distance_matching ? 1u : 0u;
    if (rt->set & MM_RUNTIME_WARPING) out->warping = rt->warping ? 1u : 0u;
    if (rt->set & MM_RUNTIME_CONTACT_FAVOUR) out->contact_favour = rt->contact_favour;
    if (rt->set & MM_RUNTIME_SPEED_ENVELOPE) out->speed_envelope = rt->speed_envelope ? 1u : 0u;
    const mm_runtime_gait *from[3] = {&rt->walk, &rt->run, &rt->crouch};
    mm_runtime_gait *to[3] = {&out->walk, &out->run, &out->crouch};
    for (int g = 0; g < 3; ++g) {
        const mm_runtime_gait *s = from[g];
        mm_runtime_gait *t = to[g];
        t->set = s->set & MM_RUNTIME_GAIT_FIELDS_ALL;
        if (s->set & MM_RUNTIME_FORWARD_SPEED) t->forward_speed = s->forward_speed;
        if (s->set & MM_RUNTIME_SIDE_SPEED) t->side_speed = s->side_speed;
        if (s->set & MM_RUNTIME_BACKWARD_SPEED) t->backward_speed = s->backward_speed;
        if (s->set & MM_RUNTIME_VELOCITY_HALFLIFE) t->velocity_halflife = s->velocity_halflife;
        if (s->set & MM_RUNTIME_ROTATION_HALFLIFE) t->rotation_halflife = s->rotation_halflife;
    }
    /* what db's locomotion covers (stored whatever the switch: mm db info shows it) */
    mm_speed_envelope envelope[MM_GAIT_COUNT];
    mm_result r = mm_speed_envelope_measure(db, NULL, envelope);
    if (r != MM_OK) return mm_error_set(err, r, 0, 0, "out of memory measuring the speed envelope");
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        memcpy(out->envelope[g], envelope[g].speeds, sizeof out->envelope[g]);
    /* the bone roles, as joints of db (the first joint of the name, as the build finds them) */
    const char *roles[MM_ROLE_COUNT] = {cfg->hips,      cfg->left_foot, cfg->right_foot, cfg->left_toe,
                                        cfg->right_toe, cfg->left_hand, cfg->right_hand, cfg->head};
    for (int k = 0; k < MM_ROLE_COUNT; ++k) {
        out->roles[k] = -1;
        for (int j = 0; roles[k][0] && j < db->joint_count && out->roles[k] < 0; ++j)
            if (strcmp(db->joints[j].name, roles[k]) == 0) out->roles[k] = j;
    }
    return mm__db_settings_validate(db, out, MM_ERR_OUT_OF_RANGE, err);
}
