// Every public header compiles as C++ (with the project's warnings) and links from C++.
#include <mm/body_mesh.h>
#include <mm/character_config.h>
#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/distance_curve.h>
#include <mm/distance_curve_build.h>
#include <mm/distance_matching.h>
#include <mm/database_build.h>
#include <mm/diagnose.h>
#include <mm/input_json.h>
#include <mm/path_json.h>
#include <mm/leg_ik.h>
#include <mm/mm.h>
#include <mm/mixer.h>
#include <mm/move_detect.h>
#include <mm/moves.h>
#include <mm/pose.h>
#include <mm/prediction.h>
#include <mm/recorder.h>
#include <mm/pfnn_character.h>
#include <mm/render.h>
#include <mm/runtime.h>
#include <mm/scene_json.h>
#include <mm/skeleton_roles.h>
#include <mm/speed_envelope.h>
#include <mm/trace.h>
#include <mm/target_match.h>
#include <mm/terrain_mesh.h>
#include <mm/view.h>
#include <mm/warp.h>

#include <cmath>
#include <cstdio>
#include <string>

int main()
{
    mm_quat q = mm_quat_from_axis_angle(mm_vec3_make(0.0f, 0.0f, 1.0f), static_cast<float>(MM_PI / 2));
    mm_vec3 v = mm_quat_rotate(q, mm_vec3_make(1.0f, 0.0f, 0.0f));
    if (std::fabs(v.y - 1.0f) > 1e-6f) {
        std::printf("rotation from C++ gave (%g %g %g)\n", v.x, v.y, v.z);
        return 1;
    }
    if (mm_result_str(MM_ERR_SYNTAX)[0] == 0) return 1;
    static mm_scene scene;
    mm_scene_init(&scene, 0.0f);
    mm_scene_hit hit;
    if (!mm_scene_raycast(&scene, mm_vec3_make(0.0f, 1.0f, 0.0f), mm_vec3_make(0.0f, -1.0f, 0.0f), 2.0f,
                          &hit) ||
        std::fabs(hit.distance - 1.0f) > 1e-6f)
        return 1;
    mm_target_match match;
    mm_target_match_init(&match, 0, mm_vec3_make(1.0f, 0.0f, 0.0f), mm_quat_identity(), 0.0f, 1.0f);
    mm_xform correction;
    if (!mm_target_match_step(&match, 0.0f, 1.0f, mm_xform_identity(), &correction) ||
        std::fabs(correction.translation.x - 1.0f) > 1e-6f)
        return 1;
    if (std::string(mm_move_kind_name(MM_MOVE_VAULT_LOW)) != "vault_low") return 1;
    if (std::string(mm_body_role_name(MM_BODY_LEFT_TOE)) != "left_toe") return 1;
    if (std::string(mm_move_kind_tag(MM_MOVE_VAULT_HIGH)) != "VaultHigh") return 1;
    mm_mixer mixer;
    mm_mixer_init(&mixer, 0, 0.0f);
    if (!mm_mixer_start(&mixer, 1, 0.0f, 0.2f, false) ||
        std::fabs(mm_mixer_weight_sum(&mixer) - 1.0f) > 1e-6f)
        return 1;
    mm_camera cam;
    mm_camera_defaults(&cam);
    float px = 0.0f, py = 0.0f;
    if (!mm_camera_project(&cam, 64, 64, cam.target, &px, &py) || std::fabs(px - 32.0f) > 1e-3f) return 1;
    std::printf("headers compile and link as C++\n");
    return 0;
}
