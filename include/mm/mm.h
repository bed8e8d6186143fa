/* mm/mm.h - umbrella header: everything public in mm's core modules.
 *
 * mm is motion matching in C: import motion capture, build a database of poses and features,
 * simulate the desired trajectory from player input, search for the best-fitting frame and
 * blend to it. Each module has its own header; include this one to get them all (link mm_build,
 * mm_pfnn and mm_runtime), or mm/runtime.h for what the mm_runtime library alone provides.
 */
#ifndef MM_MM_H
#define MM_MM_H

#include "alloc.h"
#include "bvh.h"
#include "character.h"
#include "character_config.h"
#include "clip.h"
#include "config.h"
#include "config_init.h"
#include "database.h"
#include "distance_curve.h"
#include "distance_curve_build.h"
#include "distance_matching.h"
#include "flat.h"
#include "gait.h"
#include "database_build.h"
#include "diagnose.h"
#include "import.h"
#include "input.h"
#include "leg_ik.h"
#include "math.h"
#include "pfnn.h"
#include "pose.h"
#include "prediction.h"
#include "pfnn_character.h"
#include "result.h"
#include "run.h"
#include "search.h"
#include "similarity.h"
#include "skeleton.h"
#include "skeleton_roles.h"
#include "spring.h"
#include "synth.h"
#include "trace.h"
#include "trajectory.h"
#include "version.h"
#include "warp.h"

#endif /* MM_MM_H */
