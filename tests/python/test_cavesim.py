"""The Python module against the cavesim command: same state files byte for byte, same messages,
NumPy views in the documented axis order. Run by CTest (python.pytest) with PYTHONPATH set to the
build tree's python/ folder, CAVESIM_BINARY and CAVESIM_SOURCE_DIR in the environment."""
import gc
import os
import json
import subprocess

import numpy as np
import pytest

import cavesim

SOURCE_DIR = os.environ.get("CAVESIM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ.get("CAVESIM_BINARY", os.path.join(SOURCE_DIR, "build", "cavesim"))
SMALL = os.path.join(SOURCE_DIR, "examples", "small.toml")

# examples/small.toml as a dict: the same scenario built in code.
SMALL_DICT = {
    "name": "small3d",
    "seed": 7,
    "domain": {"size": [24, 24, 8]},
    "source": [{"at": [2, 4, 6], "pressure": 1.0}, {"at": [2, 19, 5], "pressure": 0.8}],
    "sink": [{"box": [[22, 9, 0], [23, 14, 2]]}],
    "stage2.iterations": 150,
    "output": {"image_width": 256},
}


@pytest.fixture(scope="module")
def result():
    return cavesim.run(cavesim.Scenario.from_toml(SMALL), threads=2)


def cli(*args, cwd):
    return subprocess.run([BINARY, *args], cwd=cwd, capture_output=True, text=True)


def test_state_is_byte_identical_to_the_command(tmp_path, result):
    out = cli("run", SMALL, "--out", str(tmp_path / "cli"), "--quiet", "--threads", "1", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    result.write_state(tmp_path / "state.vdb")
    assert (tmp_path / "state.vdb").read_bytes() == (tmp_path / "cli" / "state.vdb").read_bytes()
    cli_report = json.loads((tmp_path / "cli" / "report.json").read_text())
    assert result.report["stage2"]["breakthrough_iteration"] == cli_report["stage2"]["breakthrough_iteration"]
    r = cavesim.run(cavesim.Scenario.from_toml(SMALL), threads=1, mesh=False, analysis=False,
                    stage1_state=tmp_path / "stage1.vdb")
    assert (tmp_path / "stage1.vdb").read_bytes() == (tmp_path / "cli" / "stage1.vdb").read_bytes()
    assert np.array_equal(r.porosity, result.porosity)


def test_grids_equal_the_commands_vdb_grids(tmp_path, result):
    vdb = pytest.importorskip("pyopenvdb")
    out = cli("run", SMALL, "--out", str(tmp_path / "cli"), "--quiet", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    nx, ny, nz = result.dims
    for name in ("porosity", "pressure", "flow"):
        grid = vdb.read(str(tmp_path / "cli" / "state.vdb"), name)
        dense = np.full((nx, ny, nz), grid.background, dtype=np.float32)  # pyopenvdb: [i, j, k]
        grid.copyToArray(dense, ijk=(0, 0, 0))
        ours = getattr(result, name)
        assert ours.shape == (nz, ny, nx)
        assert np.array_equal(dense.transpose(2, 1, 0).view(np.uint32), ours.view(np.uint32)), name


def test_axis_order_and_transform(result):
    assert result.dims == (24, 24, 8)
    for name in ("porosity", "porosity0", "pressure", "flow", "water"):
        a = getattr(result, name)
        assert a.shape == (8, 24, 24) and a.dtype == np.float32 and not a.flags.writeable, name
    assert result.flags.dtype == np.uint8 and result.zone.dtype == np.int32
    # Source 1 at voxel (i, j, k) = (2, 4, 6): element [6, 4, 2]; the sink box [[22, 9, 0], [23, 14, 2]].
    assert result.flags[6, 4, 2] & cavesim.FLAG_SOURCE
    assert result.flags[2, 14, 23] & cavesim.FLAG_SINK and not result.flags[2, 15, 23] & cavesim.FLAG_SINK
    assert result.zone[6, 4, 2] == 0 and result.zone[5, 19, 2] == 1
    assert np.all(result.pressure[0:3, 9:15, 22:24] == 0)
    m = result.world_from_index
    assert np.allclose(m @ [2, 4, 6, 1], [2.5, 4.5, 6.5, 1])
    assert np.allclose(result.index_from_world @ [2.5, 4.5, 6.5, 1], [2, 4, 6, 1])


def test_views_keep_the_result_alive():
    a = cavesim.run(SMALL, mesh=False, analysis=False).porosity  # the Result itself is dropped
    gc.collect()
    b = cavesim.run(SMALL, mesh=False, analysis=False).porosity
    assert np.array_equal(a, b) and a.base is not None


def test_from_dict_gives_the_files_results(result):
    s = cavesim.Scenario.from_dict(SMALL_DICT)
    assert s.to_toml() == cavesim.Scenario.from_toml(SMALL).to_toml()
    r = cavesim.run(s, threads=1, mesh=False, analysis=False)
    for name in ("porosity", "pressure", "flow", "flags"):
        assert np.array_equal(getattr(r, name), getattr(result, name)), name


def test_every_key_by_its_name():
    s = cavesim.Scenario()
    assert "stage2.p_rate" in cavesim.Scenario.keys() and "source" in cavesim.Scenario.keys()
    s["stage2.p_rate"] = 0.25
    assert s["stage2.p_rate"] == 0.25 and s.to_dict()["stage2"]["p_rate"] == 0.25
    s.update({"domain.size": [30, 30, 10], "source": [{"at": [1, 1, 8]}], "sink": [{"box": [[29, 0, 0], [29, 29, 2]]}]})
    assert s.size == [30, 30, 10]
    s.set("seed", np.int64(11))  # NumPy scalars are numbers
    assert s.seed == 11


def test_input_errors_carry_the_commands_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[stage2]\np_rate = -1\n')
    out = cli("validate", str(bad), cwd=tmp_path)
    assert out.returncode == 2
    with pytest.raises(cavesim.InputError) as e:
        cavesim.Scenario.from_toml(str(bad))
    assert out.stderr == f"cavesim: error: {e.value}\n"
    with pytest.raises(cavesim.InputError) as e:
        cavesim.Scenario.from_dict({"stage2": {"p_rate": -1}})
    assert str(e.value) == "<dict>: key 'stage2.p_rate' = -1: must be a number in (0, 1e+06]"
    s = cavesim.Scenario.from_toml(SMALL)
    with pytest.raises(cavesim.InputError, match="unknown key 'stage2.p_rat'"):
        s["stage2.p_rat"] = 1
    with pytest.raises(cavesim.InputError):
        s["domain.size"] = [10, 10, 4]  # the sink would lie outside
    assert s.size == [24, 24, 8]  # a failed change leaves the scenario as it was
    assert isinstance(e.value, cavesim.Error) and issubclass(cavesim.InputError, cavesim.Error)


def test_report_skeleton_and_mesh(result):
    rep = result.report
    assert rep["scenario"] == "small3d" and rep["grid"] == [24, 24, 8] and rep["threads"] == 2
    assert 0 < rep["stage2"]["breakthrough_iteration"] <= rep["stage2"]["iterations"]
    assert rep["network"]["sources_connected"] == 2
    sk = result.skeleton
    assert sk.nodes.shape == (rep["skeleton"]["nodes"], 3) and sk.edges.shape == (rep["skeleton"]["edges"], 2)
    assert sk.radii.shape == (len(sk.nodes),) and np.all(sk.radii > 0)
    assert np.all(sk.edges[:, 0] < sk.edges[:, 1]) and sk.edges.max() < len(sk.nodes)
    # Node positions are in metres, within a voxel of their centreline voxel's centre.
    centres = (sk.voxels + 0.5) * result.voxel_size
    assert np.all(np.abs(sk.nodes - centres) <= 1.0 * result.voxel_size + 1e-9)
    mesh = result.mesh
    assert mesh.vertices.dtype == np.float32 and mesh.faces.dtype == np.int32
    assert len(mesh.faces) == rep["mesh"]["faces"] and mesh.faces.max() < len(mesh.vertices)
    assert mesh.normals.shape == mesh.vertices.shape


def test_skeleton_graph(result):
    nx = pytest.importorskip("networkx")
    g = result.skeleton_graph()
    assert isinstance(g, nx.Graph)
    assert g.number_of_nodes() == len(result.skeleton.nodes)
    assert g.number_of_edges() == len(result.skeleton.edges)
    a, b = result.skeleton.edges[0]
    assert g.edges[a, b]["length"] > 0 and len(g.nodes[a]["pos"]) == 3


def test_threads_do_not_change_results(result):
    r = cavesim.run(SMALL, threads=1)
    for name in ("porosity", "pressure", "flow", "water", "flags", "zone", "cave_mask"):
        assert np.array_equal(getattr(r, name), getattr(result, name)), name
    assert np.array_equal(r.mesh.vertices, result.mesh.vertices)
    assert np.array_equal(r.skeleton.nodes, result.skeleton.nodes)


class _Stop(Exception):
    """What _stop_at's callback raises."""


def _stop_at(at):
    """A progress callback that raises _Stop when stage 2 reports iteration `at` done."""

    def stop(phase, done, total):
        if phase == "stage 2" and done == at:
            raise _Stop()

    return stop


def _cancel_at(token, at):
    """A progress callback that cancels `token` when stage 2 reports iteration `at` done."""

    def cancel(phase, done, total):
        if phase == "stage 2" and done == at:
            token.cancel()

    return cancel


def test_progress_and_cancel():
    seen = []
    cavesim.run(SMALL, progress=lambda phase, done, total: seen.append((phase, done, total)), mesh=False)
    assert ("stage 2", 150, 150) in seen and ("analysis", 1, 1) in seen
    with pytest.raises(_Stop):
        cavesim.run(SMALL, progress=_stop_at(3))
    token = cavesim.CancelToken()
    with pytest.raises(cavesim.Cancelled):
        cavesim.run(SMALL, progress=_cancel_at(token, 3), cancel=token)
    assert token.cancelled


def _without_timings(doc):
    """The report document without its timings and thread count (they differ between runs)."""
    if isinstance(doc, dict):
        return {k: _without_timings(v) for k, v in doc.items()
                if k not in ("timing_s", "threads") and "seconds" not in k}
    if isinstance(doc, list):
        return [_without_timings(v) for v in doc]
    return doc


def _expect_same_bits(a, b):
    for name in ("porosity", "porosity0", "pressure", "flow", "water", "flags", "zone", "cave_mask"):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name
    assert a.mesh.vertices.tobytes() == b.mesh.vertices.tobytes()
    assert a.mesh.faces.tobytes() == b.mesh.faces.tobytes()
    assert a.skeleton.nodes.tobytes() == b.skeleton.nodes.tobytes()
    assert _without_timings(a.report) == _without_timings(b.report)


def test_checkpoint_cancel_and_resume(tmp_path, result):
    ck = tmp_path / "small.ckpt"
    token = cavesim.CancelToken()
    with pytest.raises(cavesim.Cancelled):
        cavesim.run(SMALL, threads=2, progress=_cancel_at(token, 50), cancel=token, checkpoint_path=ck,
                    checkpoint_every=20)
    assert ck.is_file()  # the checkpoint after iteration 40
    first = []
    r = cavesim.resume(ck, threads=1, progress=lambda p, d, t: first.append(d) if p == "stage 2" else None)
    assert first[0] == 41
    _expect_same_bits(r, result)
    assert r.scenario.to_toml() == result.scenario.to_toml()

    # Stopped again by an exception in the callback, the resumed run's own checkpoint (same file) resumes.
    with pytest.raises(_Stop):
        cavesim.resume(str(ck), progress=_stop_at(95), checkpoint_path=ck, checkpoint_every=30)
    first.clear()
    _expect_same_bits(cavesim.resume(ck, progress=lambda p, d, t: first.append(d) if p == "stage 2" else None),
                      result)
    assert first[0] == 91


def test_bad_checkpoints(tmp_path):
    with pytest.raises(cavesim.InputError, match="no checkpoint to resume from"):
        cavesim.resume(tmp_path / "missing.ckpt")
    (tmp_path / "text.ckpt").write_text("not a checkpoint")
    with pytest.raises(cavesim.InputError, match="text.ckpt"):
        cavesim.resume(tmp_path / "text.ckpt")
    token = cavesim.CancelToken()
    ck = tmp_path / "good.ckpt"
    with pytest.raises(cavesim.Cancelled):
        cavesim.run(SMALL, progress=_cancel_at(token, 10), cancel=token, checkpoint_path=ck, checkpoint_every=10,
                    mesh=False)
    (tmp_path / "cut.ckpt").write_bytes(ck.read_bytes()[:-100])
    with pytest.raises(cavesim.InputError, match="cut.ckpt"):
        cavesim.resume(tmp_path / "cut.ckpt")
    with pytest.raises(cavesim.InputError):
        cavesim.run(SMALL, checkpoint_every=10)  # no path
    (tmp_path / "folder").mkdir()
    with pytest.raises(cavesim.RuntimeError, match="cannot write"):
        cavesim.run(SMALL, checkpoint_path=tmp_path / "folder", checkpoint_every=10, mesh=False, analysis=False)
