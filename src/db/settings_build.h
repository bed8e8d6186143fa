/* settings_build.h (private) - the settings section of a database, made from its config. */
#ifndef MM_DB_SETTINGS_BUILD_H
#define MM_DB_SETTINGS_BUILD_H

#include <mm/config.h>
#include <mm/database.h>

/* cfg's runtime tuning resolved against db (its joints and feature groups are read; nothing else
 * needs to be set): what mm_character_desc_apply_config would take from cfg, with set bits, and
 * the joints of cfg's bone roles. Fields not set are zero. Checked as loading checks the section:
 * MM_ERR_OUT_OF_RANGE (err names the field) for a value loading would refuse. */
mm_result mm__db_settings_resolve(const mm_config *cfg, const mm_database *db, mm_database_settings *out,
                                  mm_error *err);

#endif
