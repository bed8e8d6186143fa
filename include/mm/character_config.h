/* mm/character_config.h - a character's tuning and config files (the mm_build library): a config's
 * runtime tuning applied to a character desc at run time (mm view --config), and a desc's tuning
 * saved back into a config (the viewer's live tuning). A game reads the same tuning from the
 * database (mm_character_desc_from_database, mm/character.h) with no JSON.
 *
 * Functions: mm_character_desc_apply_config mm_config_save_tuning
 */
#ifndef MM_CHARACTER_CONFIG_H
#define MM_CHARACTER_CONFIG_H

#include "character.h"
#include "config.h"
#include "database.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Applies cfg's tuning to d: cfg's feature weights (features.bones[].position_weight /
 * velocity_weight matched by bone name, body_velocity_weight, position_multiplier,
 * angle_multiplier; only for the feature groups db has) and every field set in cfg->runtime are
 * written into d (a 0 as MM_OFF, where zero means default in d). With the config db was built from, and no
 * runtime fields set, the character behaves exactly as with d unchanged. cfg may be NULL (nothing changes).
 * For tools that apply a config file at run time (mm view --config); a game reads the same tuning from the
 * database with mm_character_desc_from_database (mm/character.h), which gives the same desc. */
void mm_character_desc_apply_config(mm_character_desc *d, const mm_database *db, const mm_config *cfg);

/* Saving writes into the config file in place: every other field keeps its value and order, the
 * result is checked as a config and written atomically (mm/config_json.h). */
/* Writes d's tuning, as the character runs with it (mm_character_desc_resolve: zero fields at
 * their defaults, MM_OFF as 0): the `runtime` object with every field (d's search parameters;
 * d's search_interval, transition_halflife and idle_speed; the walk, run and crouch gaits of
 * d->trajectory), and the feature weights under
 * `features`: features.bones[].position_weight / velocity_weight from d's
 * joint_position_weights / joint_velocity_weights, matched by bone name in db's matched-bone
 * order, and body_velocity_weight, position_multiplier, angle_multiplier, each only where db has
 * the feature group. When the config lists no bones (the defaults), the default bones are
 * written out. */
mm_result mm_config_save_tuning(const char *config_path, const mm_database *db, const mm_character_desc *d,
                                mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_CHARACTER_CONFIG_H */
