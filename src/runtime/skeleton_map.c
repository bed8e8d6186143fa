/* A character's pose in the game's skeleton (mm/skeleton_map.h). */
#include <mm/skeleton_map.h>

#include <math.h>
#include <string.h>

/* below this length an offset gives no direction for a twist axis */
#define AXIS_MIN_LENGTH 1e-6f

static int find_joint(const mm_joint *joints, int count, const char *name)
{
    if (!name) return -1;
    for (int j = 0; j < count; ++j)
        if (strcmp(joints[j].name, name) == 0) return j;
    return -1;
}

static bool finite_quat(mm_quat q)
{
    return isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w);
}

void mm_skeleton_map_free(mm_skeleton_map *map)
{
    if (!map) return;
    mm_allocator a = map->allocator;
    mm_free(&a, map->joints);
    mm_free(&a, map->source_kind);
    mm_free(&a, map->source);
    mm_free(&a, map->weight);
    mm_free(&a, map->axis);
    mm_free(&a, map->rest_rotations);
    mm_free(&a, map->rest_world);
    memset(map, 0, sizeof *map);
}

mm_result mm_skeleton_map_init(mm_skeleton_map *map, const mm_database *db, const mm_skeleton *game,
                               const mm_skeleton_map_desc *desc, mm_error *err)
{
    if (!map) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton map: no map");
    memset(map, 0, sizeof *map);
    if (!db || !game || game->joint_count < 1 || !game->joints)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "skeleton map: needs a database and a game skeleton");
    mm_result r = mm_skeleton_validate(game, err);
    if (r != MM_OK) return r;
    mm_skeleton_map_desc zero;
    memset(&zero, 0, sizeof zero);
    const mm_skeleton_map_desc *d = desc ? desc : &zero;
    int shift = d->with_root ? 1 : 0, n = game->joint_count + shift;
    if (n > MM_MAX_JOINTS)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton map: %d joints, more than %d", n,
                            MM_MAX_JOINTS);
    if (d->with_root && find_joint(game->joints, game->joint_count, db->joints[0].name) >= 0)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "skeleton map: the game's skeleton has a joint '%s' already: no root is added",
                            db->joints[0].name);
    if (d->allocator) map->allocator = *d->allocator;
    const mm_allocator *a = &map->allocator;
    size_t count = (size_t)n;
    map->joints = (mm_joint *)mm_alloc_array(a, count, sizeof *map->joints);
    map->source_kind = (int *)mm_alloc_array(a, count, sizeof *map->source_kind);
    map->source = (int *)mm_alloc_array(a, count, sizeof *map->source);
    map->weight = (float *)mm_alloc_array(a, count, sizeof *map->weight);
    map->axis = (mm_vec3 *)mm_alloc_array(a, count, sizeof *map->axis);
    map->rest_rotations = (mm_quat *)mm_alloc_array(a, count, sizeof *map->rest_rotations);
    map->rest_world = (mm_quat *)mm_alloc_array(a, count, sizeof *map->rest_world);
    if (!map->joints || !map->source_kind || !map->source || !map->weight || !map->axis ||
        !map->rest_rotations || !map->rest_world) {
        mm_skeleton_map_free(map);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "skeleton map: out of memory");
    }
    map->joint_count = n;
    map->database_joint_count = db->joint_count;
    map->game_lengths = d->game_lengths;

    /* the output skeleton: the root (with_root), then the game's joints */
    if (d->with_root) {
        map->joints[0] = db->joints[0];
        map->joints[0].parent = -1;
        map->joints[0].flags |= MM_JOINT_TRANSLATES;
        map->source_kind[0] = MM_MAP_ROOT;
        map->source[0] = 0;
        map->rest_rotations[0] = map->rest_world[0] = mm_quat_identity();
    }
    for (int g = 0; g < game->joint_count; ++g) {
        int o = g + shift;
        mm_joint *j = &map->joints[o];
        *j = game->joints[g];
        j->parent = game->joints[g].parent >= 0 ? game->joints[g].parent + shift : (d->with_root ? 0 : -1);
        mm_quat rest = d->rest_rotations ? d->rest_rotations[g] : mm_quat_identity();
        if (!finite_quat(rest) || mm_quat_length(rest) < 0.5f) {
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                             "skeleton map: the rest rotation of joint '%s' is not a rotation", j->name);
            goto fail;
        }
        map->rest_rotations[o] = mm_quat_normalize(rest);
        map->rest_world[o] = j->parent >= 0 ? mm_quat_mul(map->rest_world[j->parent], map->rest_rotations[o])
                                            : map->rest_rotations[o];
        map->source[o] = find_joint(db->joints, db->joint_count, j->name);
        map->source_kind[o] = map->source[o] >= 0 ? MM_MAP_JOINT : MM_MAP_REST;
    }
    for (int k = 0; k < d->pair_count; ++k) {
        const mm_skeleton_map_pair *p = &d->pairs[k];
        int g = find_joint(game->joints, game->joint_count, p->game);
        int s = find_joint(db->joints, db->joint_count, p->database);
        if (g < 0 || s < 0) {
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton map: pair %d: no %s joint '%s'", k,
                             g < 0 ? "game" : "database",
                             g < 0 ? (p->game ? p->game : "(null)") : p->database);
            goto fail;
        }
        map->source_kind[g + shift] = MM_MAP_JOINT;
        map->source[g + shift] = s;
    }
    for (int k = 0; k < d->follow_count; ++k) {
        const mm_skeleton_map_follow *f = &d->follow[k];
        int g = find_joint(game->joints, game->joint_count, f->game);
        int s = find_joint(db->joints, db->joint_count, f->database);
        if (g < 0 || s < 0) {
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                             "skeleton map: follower %d: no %s joint '%s'", k, g < 0 ? "game" : "database",
                             g < 0 ? (f->game ? f->game : "(null)") : f->database);
            goto fail;
        }
        int o = g + shift;
        if (map->source_kind[o] == MM_MAP_JOINT) {
            r = mm_error_set(
                err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                "skeleton map: game joint '%s' is mapped to database joint '%s' and cannot follow '%s'",
                f->game, db->joints[map->source[o]].name, f->database);
            goto fail;
        }
        if (!isfinite(f->weight)) {
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                             "skeleton map: follower '%s': weight is not finite", f->game);
            goto fail;
        }
        map->source_kind[o] = MM_MAP_FOLLOW;
        map->source[o] = s;
        map->weight[o] = f->weight;
        mm_vec3 bone = db->joints[s].offset;
        float length = mm_vec3_length(bone);
        map->axis[o] =
            f->twist && length > AXIS_MIN_LENGTH ? mm_vec3_scale(bone, 1.0f / length) : mm_vec3_make(0, 0, 0);
    }
    for (int o = shift; o < n; ++o) {
        if (map->source_kind[o] != MM_MAP_JOINT) continue;
        ++map->mapped;
        /* the written pose carries positions for what moves by itself: the roots, and joints the
         * database animates in position */
        bool translates = !d->game_lengths || map->joints[o].parent < shift ||
                          (db->joints[map->source[o]].flags & MM_JOINT_TRANSLATES);
        if (translates)
            map->joints[o].flags |= MM_JOINT_TRANSLATES;
        else
            map->joints[o].flags &= ~(unsigned)MM_JOINT_TRANSLATES;
    }
    if (map->mapped == 0) {
        r = mm_error_set(
            err, MM_ERR_INVALID_ARGUMENT, 0, 0,
            "skeleton map: no joint of the game's skeleton is a joint of the database (names differ: "
            "give pairs)");
        goto fail;
    }
    return MM_OK;
fail:
    mm_skeleton_map_free(map);
    return r;
}

/* The rotation a follower takes from its database joint's local rotation q. */
static mm_quat follow_rotation(mm_quat q, mm_vec3 axis, float weight)
{
    if (mm_vec3_length_sq(axis) > 0.0f) mm_quat_swing_twist(q, axis, NULL, &q);
    return mm_quat_exp(mm_vec3_scale(mm_quat_log(q), weight));
}

void mm_skeleton_map_pose(const mm_skeleton_map *map, const mm_xform *db_global,
                          const mm_quat *db_local_rotations, mm_quat *local_rotations,
                          mm_vec3 *local_positions, mm_xform *world)
{
    if (!map || !db_global || !world) return;
    for (int o = 0; o < map->joint_count; ++o) {
        const mm_joint *j = &map->joints[o];
        mm_xform parent = j->parent >= 0 ? world[j->parent] : mm_xform_identity();
        int s = map->source[o];
        mm_xform local = mm_xform_make(map->rest_rotations[o], j->offset);
        switch (map->source_kind[o]) {
        case MM_MAP_ROOT:
            local = db_global[0];
            break;
        case MM_MAP_JOINT: {
            mm_quat rotation = mm_quat_mul(db_global[s].rotation, map->rest_world[o]);
            mm_quat inverse = mm_quat_conj(parent.rotation);
            local.rotation = mm_quat_normalize(mm_quat_mul(inverse, rotation));
            if (j->flags & MM_JOINT_TRANSLATES) /* where the database joint stands */
                local.translation =
                    mm_quat_rotate(inverse, mm_vec3_sub(db_global[s].translation, parent.translation));
            break;
        }
        case MM_MAP_FOLLOW:
            if (db_local_rotations)
                local.rotation =
                    mm_quat_mul(follow_rotation(db_local_rotations[s], map->axis[o], map->weight[o]),
                                map->rest_rotations[o]);
            break;
        default:
            break;
        }
        world[o] = mm_xform_mul(parent, local);
        if (local_rotations) local_rotations[o] = local.rotation;
        if (local_positions) local_positions[o] = local.translation;
    }
}
