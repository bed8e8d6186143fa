"""The Python package against independent truth: the C headers' version, the database's own
structure, exact self-matches and a second search method, forward kinematics done here in numpy,
and the mm program's output for the same run and the same build."""
import os
import re
import subprocess

import numpy as np
import pytest

import mm


def test_version_is_the_headers(source_dir):
    with open(os.path.join(source_dir, "include", "mm", "version.h"), encoding="utf-8") as f:
        text = f.read()
    parts = tuple(int(re.search(r"^#define MM_VERSION_%s (\d+)$" % p, text, re.M).group(1))
                  for p in ("MAJOR", "MINOR", "PATCH"))
    assert mm.version_info() == parts
    assert mm.version() == "%d.%d.%d" % parts


def test_the_library_is_the_packages_own():
    from mm import _native

    here = os.path.dirname(os.path.abspath(mm.__file__))
    assert os.path.dirname(_native.runtime._name).startswith(here)
    assert "LD_LIBRARY_PATH" not in os.environ or here not in os.environ["LD_LIBRARY_PATH"]
    # every mm library mapped into the process is the package's copy (one runtime, not a build tree's)
    with open("/proc/self/maps", encoding="utf-8") as f:
        mapped = {line.split()[-1] for line in f if "libmm_" in line}
    assert len(mapped) == 2 and all(p.startswith(here) for p in mapped), mapped


def test_database_structure(db):
    assert db.frames > 1000
    assert db.features.shape == (db.frames, db.dims) == db.raw_features.shape
    assert db.features.dtype == np.float32 and np.isfinite(db.features).all()
    assert abs(db.fps - 60.0) < 1e-3
    # joints in topological order, one root
    assert db.parents[0] == -1 and (db.parents[1:] >= 0).all()
    assert (db.parents[1:] < np.arange(1, len(db.joints))).all()
    assert len(set(db.joints)) == len(db.joints)
    # clips tile the frames in order, and each frame knows its clip
    first = 0
    for i, c in enumerate(db.clips):
        assert c.first_frame == first and c.frame_count > 0 and c.type in ("locomotion", "idle")
        assert (db.frame_clip[c.first_frame:c.first_frame + c.frame_count] == i).all()
        last = c.first_frame + c.frame_count - 1
        assert db.frame_next[last] == (c.first_frame if c.loop else -1)
        first += c.frame_count
    assert first == db.frames
    # feature groups tile the dimensions
    assert sum(g.dims for g in db.groups) == db.dims
    assert [g.offset for g in db.groups] == list(np.cumsum([0] + [g.dims for g in db.groups])[:-1])
    assert "Walk" in db.tags and "Run" in db.tags
    walk = 1 << db.tags.index("Walk")
    assert (db.frame_tags & np.uint64(walk)).any()


def test_raw_trajectory_directions_are_unit(db):
    for g in db.groups:
        if g.name.startswith("trajectory.direction"):
            d = db.raw_features[:, g.offset:g.offset + g.dims]
            assert np.allclose(np.linalg.norm(d, axis=1), 1.0, atol=1e-3), g.name


def test_search_finds_a_frame_itself_and_agrees_with_brute_force(db):
    rng = np.random.default_rng(1)
    for frame in rng.integers(0, db.frames, 8):
        best = db.search(db.features[frame])
        # the frame itself costs 0; a lower index wins a tie (an identical frame)
        assert best.costs[0] <= 1e-6
        assert best.frames[0] == frame or np.array_equal(db.features[best.frames[0]], db.features[frame])
        assert np.all(best.terms[0] <= 1e-6)
        # excluded as the frame playing, it is not the answer
        other = db.search(db.features[frame], current_frame=int(frame), k=4)
        assert frame not in other.frames
    query = db.features[rng.integers(0, db.frames)] + rng.normal(0, 0.5, db.dims).astype(np.float32)
    fast = db.search(query, k=5)
    brute = db.search(query, k=5, method="brute")
    assert np.array_equal(fast.frames, brute.frames)
    assert np.allclose(fast.costs, brute.costs, rtol=1e-5)
    assert np.all(np.diff(fast.costs) >= 0)
    assert fast.terms.shape == (5, len(mm.COST_TERMS)) and np.all(fast.terms >= 0)
    # the terms sum to the cost where no favour applies (frames of clips that do not loop)
    for f, c, t in zip(fast.frames, fast.costs, fast.terms):
        if not db.clips[db.frame_clip[f]].loop:
            assert abs(t.sum() - c) <= 1e-4 * max(1.0, c)


def test_search_rejects_bad_queries(db):
    with pytest.raises(ValueError):
        db.search(np.zeros(db.dims + 1))
    with pytest.raises(ValueError):
        db.search(db.features[0], method="sideways")
    with pytest.raises(mm.Error):
        db.search(db.features[0], current_frame=db.frames)


def quat_rotate(q, v):
    """v rotated by unit quaternions q (x, y, z, w), both [..., 4] / [..., 3]."""
    u, w = q[..., :3], q[..., 3:4]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def quat_mul(a, b):
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz], axis=-1)


def test_simulate_random(db):
    run = mm.simulate(db, random=11, seconds=3)
    joints = len(db.joints)
    assert run.world.shape == (180, joints, 3) and run.local_rotations.shape == (180, joints, 4)
    assert np.isfinite(run.world).all()
    # forward kinematics here, from the local pose, gives the world pose the library returned
    pos = run.local_positions.astype(np.float64)
    rot = run.local_rotations.astype(np.float64)
    world_p = np.empty_like(pos)
    world_q = np.empty_like(rot)
    for j, p in enumerate(db.parents):
        if p < 0:
            world_p[:, j], world_q[:, j] = pos[:, j], rot[:, j]
        else:
            world_p[:, j] = world_p[:, p] + quat_rotate(world_q[:, p], pos[:, j])
            world_q[:, j] = quat_mul(world_q[:, p], rot[:, j])
    assert np.abs(world_p - run.world).max() < 1e-4
    assert np.abs(np.abs(np.sum(world_q * run.world_rotations, axis=-1)) - 1).max() < 1e-4
    # the root stays on the ground, the head above it; the database frames are frames
    assert np.abs(run.world[:, 0, 1]).max() < 1e-4
    assert (run.world[:, -1, 1] > 0.3).all()
    assert ((run.db_frames >= 0) & (run.db_frames < db.frames)).all()
    # the same seed gives the same bits; another seed another run
    assert np.array_equal(run.world, mm.simulate(db, random=11, seconds=3).world)
    assert not np.array_equal(run.world, mm.simulate(db, random=12, seconds=3).world)


def test_simulate_input_script_moves_as_the_stick_says(db, source_dir):
    # straight_walk.json: the stick forward (+Z) at a walk
    script = os.path.join(source_dir, "scripts", "input", "straight_walk.json")
    run = mm.simulate(db, input=script, seconds=4, fps=30)
    assert run.world.shape[0] == 120 and abs(run.times[1] - 1 / 30) < 1e-12
    travel = run.world[-1, 0] - run.world[0, 0]
    assert travel[2] > 2.0 and abs(travel[0]) < 0.5 * travel[2]


def test_simulate_argument_errors(db, tmp_path):
    with pytest.raises(NotImplementedError):
        mm.simulate(db, path="path.json", seconds=1)
    with pytest.raises(ValueError):
        mm.simulate(db, seconds=1)
    with pytest.raises(ValueError):
        mm.simulate(db, random=1, input="x.json", seconds=1)
    bad = tmp_path / "bad.json"
    bad.write_text('{"keys": [{"t": 0, "stick": [3, 0], "gait": "fly"}]}')
    with pytest.raises(mm.Error) as e:
        mm.simulate(db, input=bad, seconds=1)
    assert "bad.json" in str(e.value)


def test_bad_database_path():
    with pytest.raises(mm.Error) as e:
        mm.Database("/nonexistent/x.mmdb")
    assert "/nonexistent/x.mmdb" in str(e.value)


def test_simulate_is_mm_simulate(db, db_path, cli, tmp_path):
    """The same run as `mm simulate --random 5`, compared through its BVH and `mm bvh fk`."""
    bvh = tmp_path / "run.bvh"
    subprocess.run([cli, "simulate", db_path, "--random", "5", "--seconds", "2", "-o", str(bvh)], check=True,
                   stdout=subprocess.DEVNULL)
    run = mm.simulate(db, random=5, seconds=2)
    for frame in (0, 60, 119):
        out = subprocess.run([cli, "bvh", "fk", str(bvh), "--frame", str(frame)], check=True, capture_output=True,
                             text=True).stdout.split("\n")
        rows = [line.split() for line in out if line.strip()]
        assert [r[0] for r in rows] == db.joints
        fk = np.array([[float(x) for x in r[1:]] for r in rows])
        # the BVH keeps 6 decimals of position and degrees
        assert np.abs(fk - run.world[frame]).max() < 2e-3, frame


def test_build_is_mm_db_build(source_dir, data_dir, db_path, tmp_path):
    out = tmp_path / "python.mmdb"
    built = mm.build(os.path.join(source_dir, "configs", "synth.json"), out, data_dir=data_dir)
    assert built.frames > 0
    with open(out, "rb") as a, open(db_path, "rb") as b:
        assert a.read() == b.read()
    with pytest.raises(mm.Error) as e:
        mm.build(tmp_path / "missing.json", tmp_path / "x.mmdb")
    assert "missing.json" in str(e.value)
