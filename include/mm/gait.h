/* mm/gait.h - the gaits a player can ask for (walk, run, crouch, jump) and their names.
 *
 * The input asks for a gait (mm/input.h); a database's tags named after a gait, in any case
 * ("Walk", "run"), mark the frames of that gait: the character's search leaves out the frames
 * of the gaits the input does not ask for (mm/character.h), and mm_database_speed_summary
 * measures each gait's speeds (mm/database.h).
 *
 * Functions: mm_gait_name mm_gait_parse
 */
#ifndef MM_GAIT_H
#define MM_GAIT_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mm_gait { MM_GAIT_WALK = 0, MM_GAIT_RUN, MM_GAIT_CROUCH, MM_GAIT_JUMP, MM_GAIT_COUNT } mm_gait;

/* "walk", "run", "crouch", "jump"; NULL if invalid. */
const char *mm_gait_name(mm_gait g);
/* The gait named name, or MM_GAIT_COUNT if none. */
mm_gait mm_gait_parse(const char *name);

#ifdef __cplusplus
}
#endif

#endif /* MM_GAIT_H */
