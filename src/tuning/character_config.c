/* A character's tuning and config files: a config's tuning applied to a desc, and a desc's tuning
 * saved into a config (mm/character_config.h). */
#include <mm/character_config.h>

#include <string.h>

#include "db/settings_build.h"
#include "io/config_doc.h"
#include "io/file.h"

/* The config's settings as the build stores them, applied as the runtime applies a database's. */
void mm_character_desc_apply_config(mm_character_desc *d, const mm_database *db, const mm_config *cfg)
{
    if (!d || !db || !cfg) return;
    mm_database_settings s;
    if (mm__db_settings_resolve(cfg, db, &s, NULL) == MM_OK) mm_character_desc_apply_settings(d, &s);
}

/* The database's group of kind for the joint named name (any joint when name is NULL), or -1. */
static int find_group(const mm_database *db, int kind, const char *name)
{
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        if (grp->kind != kind) continue;
        if (!name) return g;
        if (grp->bone >= 0 && grp->bone < db->joint_count && strcmp(db->joints[grp->bone].name, name) == 0)
            return g;
    }
    return -1;
}

/* Writes the weights of the bones the database matches into bone (a features.bones entry). */
static int set_bone_weights(cJSON *bone, const mm_database *db, const mm_search_params *p, const char *name)
{
    int g = find_group(db, MM_FEATURE_BONE_POSITION, name),
        slot = g >= 0 ? mm_database_matched_bone(db, g) : -1;
    if (slot >= 0 && !mm__json_set_number(bone, "position_weight", p->joint_position_weights[slot])) return 0;
    g = find_group(db, MM_FEATURE_BONE_VELOCITY, name);
    slot = g >= 0 ? mm_database_matched_bone(db, g) : -1;
    if (slot >= 0 && !mm__json_set_number(bone, "velocity_weight", p->joint_velocity_weights[slot])) return 0;
    return 1;
}

mm_result mm_config_save_tuning(const char *config_path, const mm_database *db, const mm_character_desc *d,
                                mm_error *err)
{
    mm__error_set_file(err, config_path);
    if (!config_path || !db || !d)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a config path, database and desc are needed");
    /* the values the character runs with: zero fields at their defaults, MM_OFF as 0 */
    mm_character_desc run;
    mm_character_desc_resolve(db, d, &run);
    d = &run;
    mm_search_params params = run.params;
    mm_trajectory_desc traj;
    mm_trajectory_resolve_desc(&run.trajectory, &traj);
    float *zeroed[] = {&params.pose_trajectory_ratio,
                       &params.body_velocity_weight,
                       &params.position_multiplier,
                       &params.angle_multiplier,
                       &params.next_pose_favour,
                       &params.loop_anim_favour,
                       &params.continuing_bias,
                       &run.search_interval,
                       &run.transition_halflife,
                       &run.idle_speed,
                       &run.sync_halflife};
    for (size_t k = 0; k < sizeof zeroed / sizeof zeroed[0]; ++k)
        if (*zeroed[k] < 0.0f) *zeroed[k] = 0.0f;
    if (params.contact_mismatch_favour < 1.0f) params.contact_mismatch_favour = 1.0f; /* MM_OFF: off */
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        if (params.joint_position_weights[b] < 0.0f) params.joint_position_weights[b] = 0.0f;
        if (params.joint_velocity_weights[b] < 0.0f) params.joint_velocity_weights[b] = 0.0f;
    }

    mm_config cfg;
    cJSON *root = NULL;
    mm_result r = mm__config_doc_load(config_path, &cfg, &root, err);
    if (r != MM_OK) return r;

    /* features: the weights the search uses, for the groups the database has */
    cJSON *features = mm__json_object_at(root, "features");
    if (!features) return mm__config_doc_no_memory(root, &cfg, err);
    cJSON *bones = cJSON_GetObjectItemCaseSensitive(features, "bones");
    if (!bones) { /* the default bones: write them out to hold the weights */
        bones = cJSON_AddArrayToObject(features, "bones");
        for (int i = 0; bones && i < cfg.bone_count; ++i) {
            const mm_config_bone *cb = &cfg.bones[i];
            cJSON *o = cJSON_CreateObject();
            if (!o || !cJSON_AddItemToArray(bones, o)) {
                cJSON_Delete(o);
                return mm__config_doc_no_memory(root, &cfg, err);
            }
            if (!cJSON_AddStringToObject(o, "name", cb->name) ||
                (!(cb->features & MM_MATCH_POSITION) && !cJSON_AddFalseToObject(o, "position")) ||
                (!(cb->features & MM_MATCH_VELOCITY) && !cJSON_AddFalseToObject(o, "velocity")) ||
                ((cb->features & MM_MATCH_POSITION) &&
                 !mm__json_set_number(o, "position_weight", cb->position_weight)) ||
                ((cb->features & MM_MATCH_VELOCITY) &&
                 !mm__json_set_number(o, "velocity_weight", cb->velocity_weight)))
                return mm__config_doc_no_memory(root, &cfg, err);
        }
        if (!bones) return mm__config_doc_no_memory(root, &cfg, err);
    }
    for (int i = 0; i < cfg.bone_count; ++i) { /* array entry i is cfg.bones[i] */
        cJSON *o = cJSON_GetArrayItem(bones, i);
        if (o && !set_bone_weights(o, db, &params, cfg.bones[i].name))
            return mm__config_doc_no_memory(root, &cfg, err);
    }
    if ((find_group(db, MM_FEATURE_ROOT_VELOCITY, NULL) >= 0 &&
         !mm__json_set_number(features, "body_velocity_weight", params.body_velocity_weight)) ||
        (find_group(db, MM_FEATURE_TRAJ_POSITION, NULL) >= 0 &&
         !mm__json_set_number(features, "position_multiplier", params.position_multiplier)) ||
        (find_group(db, MM_FEATURE_TRAJ_DIRECTION, NULL) >= 0 &&
         !mm__json_set_number(features, "angle_multiplier", params.angle_multiplier)))
        return mm__config_doc_no_memory(root, &cfg, err);

    /* runtime: every field */
    cJSON *rt = mm__json_object_at(root, "runtime");
    if (!rt || !mm__json_set_number(rt, "pose_trajectory_ratio", params.pose_trajectory_ratio) ||
        !mm__json_set_number(rt, "next_pose_favour", params.next_pose_favour) ||
        !mm__json_set_number(rt, "loop_anim_favour", params.loop_anim_favour) ||
        !mm__json_set_number(rt, "contact_favour", params.contact_mismatch_favour) ||
        !mm__json_set_number(rt, "continuing_bias", params.continuing_bias) ||
        !mm__json_set_number(rt, "search_interval", d->search_interval) ||
        !mm__json_set_number(rt, "transition_halflife", d->transition_halflife) ||
        !mm__json_set_number(rt, "idle_speed", d->idle_speed) ||
        !mm__json_set_number(rt, "sync_halflife", d->sync_halflife) ||
        !mm__json_set_bool(rt, "distance_matching", d->distance_matching) ||
        !mm__json_set_bool(rt, "warping", d->warping) ||
        !mm__json_set_bool(rt, "speed_envelope", d->trajectory.bounded))
        return mm__config_doc_no_memory(root, &cfg, err);
    static const char *const gait_keys[3] = {"walk", "run", "crouch"};
    static const mm_gait gaits[3] = {MM_GAIT_WALK, MM_GAIT_RUN, MM_GAIT_CROUCH};
    for (int g = 0; g < 3; ++g) {
        const mm_gait_params *gp = &traj.gaits[gaits[g]];
        cJSON *o = mm__json_object_at(rt, gait_keys[g]);
        if (!o || !mm__json_set_number(o, "forward_speed", gp->forward_speed) ||
            !mm__json_set_number(o, "side_speed", gp->side_speed) ||
            !mm__json_set_number(o, "backward_speed", gp->backward_speed) ||
            !mm__json_set_number(o, "velocity_halflife", gp->velocity_halflife) ||
            !mm__json_set_number(o, "rotation_halflife", gp->rotation_halflife))
            return mm__config_doc_no_memory(root, &cfg, err);
    }
    mm_config_free(&cfg);
    return mm__config_doc_save(config_path, root, err);
}
