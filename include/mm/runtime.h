/* mm/runtime.h - umbrella header of the mm_runtime library: everything a game needs to play a
 * motion database (load and validate it, search it, drive characters with it) and nothing that
 * makes one. libmm_runtime needs libc, libm and pthreads only; examples/embed.c is the whole
 * embedding in an engine.
 *
 * The other libraries: mm_build (mm/database_build.h, mm/config.h, mm/config_json.h, mm/bvh.h,
 * mm/import.h, mm/synth.h, mm/similarity.h, mm/move_detect.h, mm/input_json.h, mm/path_json.h,
 * mm/scene_json.h, mm/pfnn_character.h), mm_pfnn (mm/pfnn.h), mm_render (mm/render.h, mm/view.h).
 */
#ifndef MM_RUNTIME_H
#define MM_RUNTIME_H

#include "alloc.h"
#include "character.h"
#include "clip.h"
#include "crowd.h"
#include "database.h"
#include "distance_curve.h"
#include "distance_matching.h"
#include "drive.h"
#include "gait.h"
#include "input.h"
#include "leg_ik.h"
#include "math.h"
#include "mixer.h"
#include "move_kind.h"
#include "moves.h"
#include "pose.h"
#include "prediction.h"
#include "recorder.h"
#include "result.h"
#include "run.h"
#include "scene.h"
#include "search.h"
#include "skeleton.h"
#include "skeleton_map.h"
#include "spring.h"
#include "target_match.h"
#include "trajectory.h"
#include "version.h"
#include "warp.h"

#endif /* MM_RUNTIME_H */
