"""mm from Python: load and build motion-matching databases, read their features and clips, search
them, run a character on an input script or a random seed and get its poses as numpy arrays.

    import mm
    db = mm.Database("synth.mmdb")
    run = mm.simulate(db, random=7, seconds=10)
    run.world            # [frames, joints, 3] world positions in metres

The package carries its own copy of mm's shared libraries and calls them through ctypes (the flat
API, include/mm/flat.h); nothing is re-implemented here.
"""
import ctypes
import os
from collections import namedtuple

import numpy as np

from . import _native as _n

__all__ = ["Error", "Database", "Clip", "FeatureGroup", "SearchResult", "Simulation", "version", "version_info",
           "simulate", "build", "COST_TERMS"]

_MESSAGE_SIZE = 2048
# the five cost terms of a search (mm_search_terms, mm/search.h), the columns of SearchResult.terms
COST_TERMS = ("pose_position", "pose_velocity", "root_velocity", "traj_position", "traj_direction")
_METHODS = {"fast": 0, "brute": 1, "facing": 2}
# mm_clip_type (mm/database.h)
_CLIP_TYPES = {0: "locomotion", 1: "idle"}

Clip = namedtuple("Clip", "name first_frame frame_count type loop")
FeatureGroup = namedtuple("FeatureGroup", "name offset dims weight")
SearchResult = namedtuple("SearchResult", "frames costs terms")


class Error(RuntimeError):
    """An error of the mm library: .code is its mm_result (mm/result.h), the message says what and where."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def _check(code, message):
    if code != 0:
        text = message.value.decode("utf-8", "replace") or _n.mm_result_str(code).decode()
        raise Error(code, text)


def _path(p):
    return os.fsencode(os.fspath(p))


def _ptr(array, ctype):
    return array.ctypes.data_as(ctypes.POINTER(ctype))


def version():
    """The version of the mm library in use, "MAJOR.MINOR.PATCH" (mm_version_string())."""
    return _n.mm_version_string().decode()


def version_info():
    """The same as a tuple (major, minor, patch), from mm_version()."""
    v = _n.mm_version()
    return (v // 10000, v // 100 % 100, v % 100)


class Database:
    """A motion database (.mmdb), loaded (mapped and validated) by the library.

    frames, joints (names), parents, interval (seconds per frame), clips, tags, groups (feature
    groups); features ([frames, dims], normalised as the search sees them) and raw_features (in
    metres, m/s and unit directions of the character frame); frame_clip, frame_next, frame_tags.
    """

    def __init__(self, path):
        self.path = os.fspath(path)
        message = ctypes.create_string_buffer(_MESSAGE_SIZE)
        self._handle = _n.database_load(_path(path), message, _MESSAGE_SIZE)
        if not self._handle:
            raise Error(-1, message.value.decode("utf-8", "replace"))
        h = self._handle
        self.frames = _n.database_count(h, _n.FRAMES)
        self.dims = _n.database_count(h, _n.DIMS)
        self.interval = float(_n.database_interval(h))
        parent = ctypes.c_int()
        names = []
        parents = []
        for j in range(_n.database_count(h, _n.JOINTS)):
            names.append(_n.joint(h, j, ctypes.byref(parent)).decode())
            parents.append(parent.value)
        self.joints = names
        self.parents = np.array(parents, dtype=np.int32)
        first, count, kind, loop = ctypes.c_int(), ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
        self.clips = []
        for i in range(_n.database_count(h, _n.CLIPS)):
            name = _n.clip(h, i, ctypes.byref(first), ctypes.byref(count), ctypes.byref(kind), ctypes.byref(loop))
            self.clips.append(Clip(name.decode(), first.value, count.value,
                                   _CLIP_TYPES.get(kind.value, str(kind.value)), bool(loop.value)))
        self.tags = [_n.tag_name(h, i).decode() for i in range(_n.database_count(h, _n.TAGS))]
        offset, dims, weight = ctypes.c_int(), ctypes.c_int(), ctypes.c_float()
        self.groups = []
        for i in range(_n.database_count(h, _n.GROUPS)):
            name = _n.group(h, i, ctypes.byref(offset), ctypes.byref(dims), ctypes.byref(weight))
            self.groups.append(FeatureGroup(name.decode(), offset.value, dims.value, float(weight.value)))
        self._features = {}
        self._frame_info = None

    def _live(self):
        if not self._handle:
            raise ValueError("mm.Database: closed")
        return self._handle

    def close(self):
        """Frees the database (the object is unusable afterwards); also on garbage collection."""
        if getattr(self, "_handle", None):
            _n.database_free(self._handle)
            self._handle = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return "mm.Database(%r: %d frames, %d joints, %d clips)" % (self.path, self.frames, len(self.joints),
                                                                    len(self.clips))

    @property
    def fps(self):
        return 1.0 / self.interval

    def _feature_array(self, raw):
        if raw not in self._features:
            out = np.empty((self.frames, self.dims), dtype=np.float32)
            _n.features(self._live(), int(raw), _ptr(out, ctypes.c_float))
            out.flags.writeable = False
            self._features[raw] = out
        return self._features[raw]

    @property
    def features(self):
        """[frames, dims] float32: the features as the search compares them (normalised)."""
        return self._feature_array(False)

    @property
    def raw_features(self):
        """[frames, dims] float32: the features in their units (metres, m/s, unit directions)."""
        return self._feature_array(True)

    def _frames_of(self):
        if self._frame_info is None:
            clip = np.empty(self.frames, dtype=np.int32)
            nxt = np.empty(self.frames, dtype=np.int32)
            tags = np.empty(self.frames, dtype=np.uint64)
            _n.frame_clips(self._live(), _ptr(clip, ctypes.c_int32), _ptr(nxt, ctypes.c_int32),
                           _ptr(tags, ctypes.c_uint64))
            self._frame_info = (clip, nxt, tags)
        return self._frame_info

    @property
    def frame_clip(self):
        """[frames] int32: each frame's clip (an index into clips)."""
        return self._frames_of()[0]

    @property
    def frame_next(self):
        """[frames] int32: the frame after each (-1 at the end of a clip that does not loop)."""
        return self._frames_of()[1]

    @property
    def frame_tags(self):
        """[frames] uint64: each frame's tags, bit i for tags[i]."""
        return self._frames_of()[2]

    def search(self, query, current_frame=-1, k=1, method="fast"):
        """The best k frames for a query of normalised features ([dims], as a row of features) with
        the database's default weights: SearchResult(frames [k], costs [k], terms [k, 5] in the
        order of COST_TERMS, which sum to a frame's cost before favours). current_frame: the frame
        playing (excluded; -1: none). method: "fast" (the exact tree), "brute" or "facing"."""
        q = np.ascontiguousarray(query, dtype=np.float32).reshape(-1)
        if q.shape[0] != self.dims:
            raise ValueError("mm.Database.search: a query has %d features, not %d" % (self.dims, q.shape[0]))
        if method not in _METHODS:
            raise ValueError("mm.Database.search: method is one of %s" % ", ".join(_METHODS))
        k = int(k)
        if k < 1:
            raise ValueError("mm.Database.search: k must be at least 1")
        frames = np.empty(k, dtype=np.int32)
        costs = np.empty(k, dtype=np.float32)
        terms = np.empty((k, len(COST_TERMS)), dtype=np.float32)
        message = ctypes.create_string_buffer(_MESSAGE_SIZE)
        found = _n.search(self._live(), _ptr(q, ctypes.c_float), int(current_frame), _METHODS[method], k,
                          _ptr(frames, ctypes.c_int32), _ptr(costs, ctypes.c_float), _ptr(terms, ctypes.c_float),
                          message, _MESSAGE_SIZE)
        _check(-found if found < 0 else 0, message)
        return SearchResult(frames[:found], costs[:found], terms[:found])


class Simulation:
    """What a character did, tick by tick (mm_run_script, mm/run.h): world ([frames, joints, 3]
    world positions, metres), world_rotations ([frames, joints, 4], quaternions x y z w),
    local_positions and local_rotations (relative to each joint's parent; joint 0, the simulation
    root on the ground, relative to the world), db_frames (the database frame playing), times
    (seconds at each tick), joints and parents (the database's), fps."""

    def __init__(self, db, frames, fps):
        joints = len(db.joints)
        self.joints = list(db.joints)
        self.parents = db.parents.copy()
        self.fps = fps
        self.times = np.arange(frames, dtype=np.float64) / fps
        self.world = np.empty((frames, joints, 3), dtype=np.float32)
        self.world_rotations = np.empty((frames, joints, 4), dtype=np.float32)
        self.local_positions = np.empty((frames, joints, 3), dtype=np.float32)
        self.local_rotations = np.empty((frames, joints, 4), dtype=np.float32)
        self.db_frames = np.empty(frames, dtype=np.int32)

    @property
    def frames(self):
        return self.world.shape[0]

    def __repr__(self):
        return "mm.Simulation(%d frames at %g fps, %d joints)" % (self.frames, self.fps, len(self.joints))


def simulate(db, *, seconds, random=None, input=None, path=None, fps=60.0):
    """Runs one character of db (a Database or a .mmdb path) for `seconds` at `fps` ticks per
    second on a random input from seed `random` or on the input script `input` (JSON, as
    `mm simulate --input`), exactly as `mm simulate` does, and returns a Simulation.
    `path` (a desired path to follow) is not available yet."""
    if path is not None:
        raise NotImplementedError("mm.simulate(path=...): path following is not in the library yet; "
                                  "use random= or input=")
    if (random is None) == (input is None):
        raise ValueError("mm.simulate: give one of random=SEED or input=SCRIPT.json")
    if random is not None and (int(random) != random or random < 0):
        raise ValueError("mm.simulate: random must be a seed >= 0")
    if not seconds > 0 or not fps > 0:
        raise ValueError("mm.simulate: seconds and fps must be > 0")
    if not isinstance(db, Database):
        db = Database(db)
    frames = _n.mm_run_frames(float(seconds), float(fps))
    run = Simulation(db, frames, float(fps))
    message = ctypes.create_string_buffer(_MESSAGE_SIZE)
    code = _n.simulate(db._live(), None if input is None else _path(input), 0 if random is None else int(random),
                       float(seconds), float(fps), _ptr(run.world, ctypes.c_float),
                       _ptr(run.world_rotations, ctypes.c_float), _ptr(run.local_positions, ctypes.c_float),
                       _ptr(run.local_rotations, ctypes.c_float), _ptr(run.db_frames, ctypes.c_int32), message,
                       _MESSAGE_SIZE)
    _check(code, message)
    return run


def build(config, output, data_dir=None, threads=1):
    """Builds a database from a config (JSON; docs/config.md) as `mm db build CONFIG --data DIR
    -o OUTPUT` does (the same bytes), and returns it loaded."""
    message = ctypes.create_string_buffer(_MESSAGE_SIZE)
    code = _n.build_database(_path(config), None if data_dir is None else _path(data_dir), _path(output),
                             int(threads), message, _MESSAGE_SIZE)
    _check(code, message)
    return Database(output)
