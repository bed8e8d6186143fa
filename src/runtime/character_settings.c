/* A character's settings from the database's settings section (mm_database_settings): the runtime
 * tuning and bone roles the database was built with, in binary. No JSON, no allocation. The build
 * library's mm_character_desc_apply_config (src/tuning/) gives the same desc from the config itself
 * (tests/test_settings.c compares them). */
#include <mm/character.h>
#include <mm/moves.h>

#include <string.h>

/* A stored value for a desc field where zero means default: 0 stays 0 (MM_OFF). */
static float kept(float v) { return v == 0.0f ? MM_OFF : v; }

void mm_character_desc_apply_settings(mm_character_desc *d, const mm_database_settings *s)
{
    if (!d || !s) return;
    /* the feature weights the config gave the database's groups */
    mm_search_params *p = &d->params;
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        if ((s->position_set >> b) & 1u) p->joint_position_weights[b] = kept(s->joint_position_weights[b]);
        if ((s->velocity_set >> b) & 1u) p->joint_velocity_weights[b] = kept(s->joint_velocity_weights[b]);
    }
    if (s->weight_set & MM_SETTINGS_BODY_VELOCITY_WEIGHT)
        p->body_velocity_weight = kept(s->body_velocity_weight);
    if (s->weight_set & MM_SETTINGS_POSITION_MULTIPLIER)
        p->position_multiplier = kept(s->position_multiplier);
    if (s->weight_set & MM_SETTINGS_ANGLE_MULTIPLIER) p->angle_multiplier = kept(s->angle_multiplier);

    /* the runtime fields set */
    if (s->set & MM_RUNTIME_POSE_TRAJECTORY_RATIO) p->pose_trajectory_ratio = kept(s->pose_trajectory_ratio);
    if (s->set & MM_RUNTIME_NEXT_POSE_FAVOUR) p->next_pose_favour = kept(s->next_pose_favour);
    if (s->set & MM_RUNTIME_LOOP_ANIM_FAVOUR) p->loop_anim_favour = kept(s->loop_anim_favour);
    if (s->set & MM_RUNTIME_CONTINUING_BIAS) p->continuing_bias = kept(s->continuing_bias);
    if (s->set & MM_RUNTIME_CONTACT_FAVOUR) p->contact_mismatch_favour = s->contact_favour; /* >= 1 */
    if (s->set & MM_RUNTIME_SEARCH_INTERVAL) d->search_interval = kept(s->search_interval);
    if (s->set & MM_RUNTIME_TRANSITION_HALFLIFE) d->transition_halflife = kept(s->transition_halflife);
    if (s->set & MM_RUNTIME_IDLE_SPEED) d->idle_speed = kept(s->idle_speed);
    if (s->set & MM_RUNTIME_SYNC_HALFLIFE) d->sync_halflife = kept(s->sync_halflife);
    if (s->set & MM_RUNTIME_DISTANCE_MATCHING) d->distance_matching = s->distance_matching != 0;
    if (s->set & MM_RUNTIME_WARPING) d->warping = s->warping != 0;
    const mm_runtime_gait *from[3] = {&s->walk, &s->run, &s->crouch};
    const mm_gait to[3] = {MM_GAIT_WALK, MM_GAIT_RUN, MM_GAIT_CROUCH};
    for (int g = 0; g < 3; ++g) {
        const mm_runtime_gait *a = from[g];
        mm_gait_params *t = &d->trajectory.gaits[to[g]];
        if (a->set & MM_RUNTIME_FORWARD_SPEED) t->forward_speed = kept(a->forward_speed);
        if (a->set & MM_RUNTIME_SIDE_SPEED) t->side_speed = kept(a->side_speed);
        if (a->set & MM_RUNTIME_BACKWARD_SPEED) t->backward_speed = kept(a->backward_speed);
        if (a->set & MM_RUNTIME_VELOCITY_HALFLIFE) t->velocity_halflife = kept(a->velocity_halflife);
        if (a->set & MM_RUNTIME_ROTATION_HALFLIFE) t->rotation_halflife = kept(a->rotation_halflife);
    }
    /* the speed envelope the build measured, unless the config turned it off */
    d->trajectory.bounded = !(s->set & MM_RUNTIME_SPEED_ENVELOPE) || s->speed_envelope != 0;
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        memcpy(d->trajectory.envelopes[g].speeds, s->envelope[g], sizeof d->trajectory.envelopes[g].speeds);
}

mm_result mm_character_desc_from_database(mm_character_desc *d, const mm_database *db, mm_error *err)
{
    if (!d) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no desc");
    mm_character_defaults(d);
    if (!db) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no database");
    if (!db->settings) return MM_OK;
    mm_character_desc_apply_settings(d, db->settings);
    /* the feet stay NULL: the character takes the database's foot roles itself */
    return MM_OK;
}

void mm_moves_desc_from_database(mm_moves_desc *d, const mm_database *db)
{
    (void)db; /* the moves take the database's hand and foot roles themselves (mm_moves_init) */
    if (d) mm_moves_defaults(d);
}
