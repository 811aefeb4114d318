"""cavesim: cave-like channel networks after Pytel & Mann (JCGT 2015), from Python.

    import cavesim
    s = cavesim.Scenario.from_toml("scenarios/fig10.toml")    # or Scenario.from_dict({...})
    s["stage2.p_rate"] = 0.4                                  # any scenario key, by its TOML name
    r = cavesim.run(s, threads=2, progress=lambda phase, done, total: None)
    # or with a checkpoint every 50 stage-2 iterations, finished later by cavesim.resume("run.ckpt")
    r = cavesim.run(s, checkpoint_path="run.ckpt", checkpoint_every=50)
    r.porosity            # NumPy float32 array, shape (nz, ny, nx): r.porosity[k, j, i]
    r.skeleton.nodes      # (n, 3) node positions in metres; r.skeleton.edges (m, 2)
    r.report["stage2"]["breakthrough_iteration"]
    r.mesh.vertices, r.mesh.faces

Axes: grids are indexed [k, j, i] = [z, y, x] (C order over the simulation's x-fastest storage,
no copy); voxel (i, j, k) has its centre at ((i, j, k) + 0.5) * voxel_size metres
(`Result.world_from_index`). Meshes and skeletons are in metres, world space, z up.

Errors: a bad scenario, key or value raises `cavesim.InputError` with the message the `cavesim`
command prints; `cavesim.RuntimeError` a failure while running; `cavesim.Cancelled` a cancelled
run. All derive from `cavesim.Error`. The guide: docs/library.md.
"""

import json as _json
from collections import namedtuple as _namedtuple

import numpy as _np

from ._cavesim import (  # noqa: F401
    FLAG_CHANNEL,
    FLAG_FEATURE_CHANNEL,
    FLAG_FRACTURE,
    FLAG_OBSTACLE,
    FLAG_PROTOCHANNEL,
    FLAG_SINK,
    FLAG_SOURCE,
    CancelToken,
    Cancelled,
    Error,
    InputError,
    InternalError,
    RuntimeError,
    Scenario,
    __version__,
)
from . import _cavesim

Mesh = _namedtuple("Mesh", "vertices faces normals")
Mesh.__doc__ = """The smooth closed cave surface (cave.obj's triangles): vertices (n, 3) float32 in
metres, faces (m, 3) int32 counter-clockwise seen from the rock, normals (n, 3) out of the cave."""

Skeleton = _namedtuple("Skeleton", "nodes edges radii voxels")
Skeleton.__doc__ = """The cave's centreline graph (skeleton.json): nodes (n, 3) float64 positions in
metres, edges (m, 2) int32 node indices (a < b), radii (n,) metres to the nearest wall, voxels
(n, 3) int32 (i, j, k) of each node's centreline voxel."""


class Result:
    """What `run` produced: grids, cave mask, mesh, skeleton and report.

    Grid arrays are read-only views of the result's memory (they keep it alive), shape
    (nz, ny, nx), indexed [k, j, i]."""

    def __init__(self, impl):
        self._r = impl

    # Grids (NumPy views, no copy).
    porosity = property(lambda self: self._r.porosity, doc="float32 porosity, as state.vdb records it")
    porosity0 = property(lambda self: self._r.porosity0, doc="float32 porosity as built, before the stages")
    pressure = property(lambda self: self._r.pressure, doc="float32 stage-2 pressure")
    flow = property(lambda self: self._r.flow, doc="float32 stage-2 flow of the last iteration")
    water = property(lambda self: self._r.water, doc="float32 stage-2 water contents")
    flags = property(lambda self: self._r.flags, doc="uint8 FLAG_* bits")
    zone = property(lambda self: self._r.zone, doc="int32 stage-1 zone (source index), -1 where none")
    cave_mask = property(lambda self: self._r.cave_mask, doc="uint8, 1 where a voxel is cave")

    @property
    def dims(self):
        """(nx, ny, nz): the grid's size in voxels (the arrays' shape is the reverse)."""
        return tuple(self._r.dims)

    @property
    def voxel_size(self):
        """Edge of a voxel in metres."""
        return self._r.voxel_size

    @property
    def world_from_index(self):
        """4 × 4 matrix: world (x, y, z, 1) in metres = M @ (i, j, k, 1), voxel centres at integers."""
        h = self._r.voxel_size
        m = _np.diag([h, h, h, 1.0])
        m[:3, 3] = 0.5 * h
        return m

    @property
    def index_from_world(self):
        """4 × 4 matrix: index-space (i, j, k, 1) = M @ (x, y, z, 1); round to get the voxel."""
        return _np.linalg.inv(self.world_from_index)

    @property
    def mesh(self):
        return Mesh(self._r.mesh_vertices, self._r.mesh_faces, self._r.mesh_normals)

    @property
    def skeleton(self):
        return Skeleton(self._r.skeleton_positions, self._r.skeleton_edges, self._r.skeleton_radii,
                        self._r.skeleton_voxels)

    def skeleton_graph(self):
        """The skeleton as a networkx.Graph: node attributes `pos` (metres), `radius` (metres),
        `voxel` (i, j, k); edge attribute `length` (metres). Needs networkx."""
        try:
            import networkx as nx
        except ImportError as e:  # pragma: no cover - depends on the machine
            raise ImportError("Result.skeleton_graph() needs networkx (apt-get install python3-networkx)") from e
        sk = self.skeleton
        g = nx.Graph()
        for n in range(len(sk.nodes)):
            g.add_node(n, pos=tuple(float(x) for x in sk.nodes[n]), radius=float(sk.radii[n]),
                       voxel=tuple(int(x) for x in sk.voxels[n]))
        for a, b in sk.edges:
            g.add_edge(int(a), int(b), length=float(_np.linalg.norm(sk.nodes[a] - sk.nodes[b])))
        return g

    @property
    def report(self):
        """The report.json document of this run as a dict ("files" is empty: nothing was written)."""
        return _json.loads(self._r.report_json)

    @property
    def report_json(self):
        return self._r.report_json

    @property
    def scenario(self):
        return self._r.scenario

    def write_state(self, path):
        """Writes state.vdb as `cavesim run` does: byte for byte the same file for the same scenario."""
        self._r.write_state(str(path))

    def __repr__(self):
        nx_, ny_, nz_ = self.dims
        return f"<cavesim.Result of '{self.scenario.name}' {nx_}x{ny_}x{nz_}>"


def run(scenario, threads=0, progress=None, cancel=None, mesh=True, analysis=True, stage1_state=None,
        checkpoint_path=None, checkpoint_every=0):
    """Runs `scenario` (a Scenario, a dict or a path to a .toml file) and returns a Result.

    threads: worker threads, 0 for all cores (results do not depend on it).
    progress: called as progress(phase, done, total) with the GIL held; raising in it stops the run
        (the exception is re-raised here), as does Ctrl-C.
    cancel: a CancelToken; cancelling it (from any thread) raises cavesim.Cancelled.
    mesh, analysis: build the cave mesh / skeletonize and measure the cave.
    stage1_state: a path to write stage1.vdb to after stage 1, as `cavesim run` does.
    checkpoint_path, checkpoint_every: after every checkpoint_every-th stage-2 iteration (0: none),
        write a checkpoint to checkpoint_path, replacing the previous one atomically, so the file
        always holds the newest complete checkpoint however the run stops (an exception, a cancel,
        a crash). `resume(checkpoint_path)` finishes the run with the same grids and report numbers.
        The file is the one `cavesim run --checkpoint-every` writes; it stays after the run. A bad
        interval or a path in no folder raises cavesim.InputError; a failed write
        cavesim.RuntimeError.
    """
    if isinstance(scenario, dict):
        scenario = Scenario.from_dict(scenario)
    elif not isinstance(scenario, Scenario):
        scenario = Scenario.from_toml(str(scenario))
    impl = _cavesim._run(scenario, **_options(threads, progress, cancel, mesh, analysis, stage1_state,
                                              checkpoint_path, checkpoint_every))
    return Result(impl)


def resume(path, threads=0, progress=None, cancel=None, mesh=True, analysis=True, stage1_state=None,
           checkpoint_path=None, checkpoint_every=0):
    """Finishes a run from the checkpoint file at `path` and returns its Result.

    The checkpoint holds the scenario (its text and seed), so none is given; it may come from
    `run(..., checkpoint_path=...)` or from `cavesim run --checkpoint-every N`
    (DIR's checkpoint is .DIR.checkpoint/checkpoint.cavesim beside it). Stage 1 runs again
    (deterministic) and stage 2 continues after the checkpoint's iteration: the grids and the
    report's numbers (timings aside) are those of a run that never stopped, whatever `threads`.
    The other arguments are run's; with checkpoint_path (it may be `path` itself) and
    checkpoint_every the resumed run writes checkpoints in turn.
    Raises cavesim.InputError when the file is missing, cut or damaged, or no longer matches its
    scenario.
    """
    impl = _cavesim._resume(str(path), **_options(threads, progress, cancel, mesh, analysis, stage1_state,
                                                  checkpoint_path, checkpoint_every))
    return Result(impl)


def _options(threads, progress, cancel, mesh, analysis, stage1_state, checkpoint_path, checkpoint_every):
    return dict(threads=int(threads), progress=progress, cancel=cancel if cancel is not None else CancelToken(),
                mesh=bool(mesh), analysis=bool(analysis),
                stage1_state="" if stage1_state is None else str(stage1_state),
                checkpoint_path="" if checkpoint_path is None else str(checkpoint_path),
                checkpoint_every=int(checkpoint_every))


__all__ = ["Scenario", "Result", "Mesh", "Skeleton", "CancelToken", "run", "resume", "Error", "InputError", "RuntimeError",
           "InternalError", "Cancelled", "__version__"] + [n for n in dir() if n.startswith("FLAG_")]
