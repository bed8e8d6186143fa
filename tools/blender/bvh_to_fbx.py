# bvh_to_fbx.py - Blender script of `mm convert`: several BVH files into one FBX, one take each.
#
#   blender --background --factory-startup --python-exit-code 2 --python bvh_to_fbx.py -- \
#       OUT.fbx IN1.bvh [IN2.bvh ...]
#
# Each BVH is imported (bpy.ops.import_anim.bvh) into an action named after the file; all files
# must have the same joints (mm convert batches them so) and share the first one's armature, so
# the FBX has one skeleton and one take per file ("<first file>|<file>", Blender's
# "object|action" take names). The scene runs at the first
# file's frame rate; files at another rate are scaled in time to it. The export
# (bpy.ops.export_scene.fbx) bakes every action (bake_anim_use_all_actions), keeps every key
# (no simplification), adds leaf bones for the End Sites, and keeps the BVH's numbers as they
# are (apply_unit_scale off: the FBX declares centimetres, FBX's default unit).
import os
import sys

import bpy


def fail(message):
    print("bvh_to_fbx.py: " + message, file=sys.stderr)
    sys.exit(1)


def frame_time(path):
    with open(path, "r", errors="replace") as f:
        for line in f:
            words = line.replace(":", " ").split()
            if len(words) >= 3 and words[0].lower() == "frame" and words[1].lower() == "time":
                return float(words[2])
    fail("%s: no 'Frame Time' line" % path)


def patch_bvh_importer():
    # Blender 3.4's BVH importer opens files with mode 'rU', which Python 3.11 (Debian's Blender
    # runs on the system Python) refuses; 'r' means the same since Python 3.
    try:
        from io_anim_bvh import import_bvh
    except ImportError:
        return
    builtin_open = open

    def open_without_u(file, mode="r", *args, **kwargs):
        return builtin_open(file, mode.replace("U", ""), *args, **kwargs)

    import_bvh.open = open_without_u


def main():
    patch_bvh_importer()
    if "--" not in sys.argv:
        fail("usage: blender --background --python bvh_to_fbx.py -- OUT.fbx IN.bvh...")
    args = sys.argv[sys.argv.index("--") + 1:]
    if len(args) < 2:
        fail("usage: blender --background --python bvh_to_fbx.py -- OUT.fbx IN.bvh...")
    out, files = args[0], args[1:]

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    rate = scene_rate = 1.0 / frame_time(files[0])
    scene.render.fps = max(1, int(round(rate)))
    scene.render.fps_base = 1.0
    if abs(scene.render.fps - rate) > 1e-3 * rate:  # not a whole number of frames per second
        scene.render.fps_base = scene.render.fps / rate
    else:
        scene_rate = scene.render.fps

    first = first_key = None
    end = 1
    for path in files:
        name = os.path.splitext(os.path.basename(path))[0]
        before = set(bpy.data.objects)
        result = bpy.ops.import_anim.bvh(
            filepath=path,
            global_scale=1.0,
            frame_start=1,
            # BVH frames map 1:1 to scene frames at the scene's rate, else they are scaled in time
            use_fps_scale=abs(1.0 / frame_time(path) - scene_rate) > 1e-3 * scene_rate,
            update_scene_fps=False,
            update_scene_duration=False,
            rotate_mode="NATIVE",
            axis_forward="-Z",
            axis_up="Y",
        )
        if "FINISHED" not in result:
            fail("%s: Blender's BVH importer failed" % path)
        new = [o for o in bpy.data.objects if o not in before and o.type == "ARMATURE"]
        if len(new) != 1 or not new[0].animation_data or not new[0].animation_data.action:
            fail("%s: the import made no animated armature" % path)
        ob = new[0]
        action = ob.animation_data.action
        action.name = name
        action.use_fake_user = True
        end = max(end, int(action.frame_range[1]))
        key = tuple(sorted(b.name for b in ob.data.bones))
        if first is None:
            ob.name = name
            first, first_key = ob, key
        else:
            # Every other action is exported on the first armature (bake_anim_use_all_actions
            # takes each action whose curves all resolve on it): one skeleton, one take per file.
            if key != first_key:
                fail("%s: its joints differ from those of %s; give files of one skeleton" % (path, files[0]))
            ob.animation_data.action = None
            bpy.data.objects.remove(ob, do_unlink=True)
    scene.frame_start = 1
    scene.frame_end = end

    result = bpy.ops.export_scene.fbx(
        filepath=out,
        use_selection=False,
        object_types={"ARMATURE"},
        # Blender takes its units for metres and FBX's for centimetres, so it would multiply by
        # 100: 0.01 keeps the BVH's numbers (and the FBX declares centimetres).
        apply_unit_scale=False,
        apply_scale_options="FBX_SCALE_NONE",
        global_scale=0.01,
        axis_forward="-Z",
        axis_up="Y",
        add_leaf_bones=True,
        primary_bone_axis="Y",
        secondary_bone_axis="X",
        armature_nodetype="NULL",
        bake_anim=True,
        bake_anim_use_all_bones=True,
        bake_anim_use_nla_strips=False,
        bake_anim_use_all_actions=True,
        bake_anim_force_startend_keying=True,
        bake_anim_step=1.0,
        bake_anim_simplify_factor=0.0,
    )
    if "FINISHED" not in result or not os.path.isfile(out):
        fail("%s: Blender's FBX exporter failed" % out)
    print("bvh_to_fbx.py: wrote %s (%d takes)" % (out, len(files)))


main()
