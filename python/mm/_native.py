"""The package's copy of mm's shared libraries, loaded with ctypes, and the prototypes of the flat
API (include/mm/flat.h) and of mm/version.h and mm/run.h that the package calls."""
import ctypes
import glob
import os

_HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_lib")


def _load(name, mode):
    found = sorted(glob.glob(os.path.join(_HERE, "lib%s.so*" % name)), key=len)
    if not found:
        raise ImportError("mm: lib%s.so is missing from %s (reinstall the package)" % (name, _HERE))
    return ctypes.CDLL(found[0], mode=mode)


# libmm_build needs libmm_runtime (by its soname): loaded first, by path, it is the one used
runtime = _load("mm_runtime", ctypes.RTLD_GLOBAL)
build = _load("mm_build", ctypes.RTLD_LOCAL)

c_int, c_float, c_double, c_char_p, c_void_p, c_size_t = (ctypes.c_int, ctypes.c_float, ctypes.c_double,
                                                          ctypes.c_char_p, ctypes.c_void_p, ctypes.c_size_t)
P_int, P_float, P_int32, P_uint64 = (ctypes.POINTER(c_int), ctypes.POINTER(c_float),
                                     ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_uint64))


def _proto(lib, name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)
    return f


mm_version = _proto(runtime, "mm_version", c_int)
mm_version_string = _proto(runtime, "mm_version_string", c_char_p)
mm_result_str = _proto(runtime, "mm_result_str", c_char_p, c_int)
mm_run_frames = _proto(runtime, "mm_run_frames", c_int, c_double, c_double)

database_load = _proto(build, "mm_flat_database_load", c_void_p, c_char_p, c_char_p, c_size_t)
database_free = _proto(build, "mm_flat_database_free", None, c_void_p)
database_count = _proto(build, "mm_flat_database_count", c_int, c_void_p, c_int)
database_interval = _proto(build, "mm_flat_database_interval", c_float, c_void_p)
joint = _proto(build, "mm_flat_joint", c_char_p, c_void_p, c_int, P_int)
clip = _proto(build, "mm_flat_clip", c_char_p, c_void_p, c_int, P_int, P_int, P_int, P_int)
tag_name = _proto(build, "mm_flat_tag_name", c_char_p, c_void_p, c_int)
group = _proto(build, "mm_flat_group", c_char_p, c_void_p, c_int, P_int, P_int, P_float)
features = _proto(build, "mm_flat_features", None, c_void_p, c_int, P_float)
frame_clips = _proto(build, "mm_flat_frame_clips", None, c_void_p, P_int32, P_int32, P_uint64)
search = _proto(build, "mm_flat_search", c_int, c_void_p, P_float, c_int, c_int, c_int, P_int32, P_float, P_float,
                c_char_p, c_size_t)
simulate = _proto(build, "mm_flat_simulate", c_int, c_void_p, c_char_p, ctypes.c_uint64, c_double, c_double,
                  P_float, P_float, P_float, P_float, P_int32, c_char_p, c_size_t)
build_database = _proto(build, "mm_flat_build", c_int, c_char_p, c_char_p, c_char_p, c_int, c_char_p, c_size_t)

# the order of mm_flat_count
FRAMES, JOINTS, CLIPS, TAGS, GROUPS, DIMS = range(6)
