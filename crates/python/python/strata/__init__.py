"""strata: reservoir simulation grids read, drawn and measured, from Python.

The same readers, scene and renderer as the ``strata`` command line, with models
in and pictures out as numpy arrays::

    import strata
    grid = strata.open("REEK.EGRID", props=["reek_sim_poro.grdecl"])
    grid.properties["PORO"]            # masked (nx, ny, nz), inactive cells masked
    picture = strata.render(grid, strata.Scene(sides=True, size=[800, 600]))
    picture.save("reek.png")           # or show it: Jupyter calls _repr_png_

Errors are :class:`StrataError` subclasses carrying the command line's messages
(file, keyword, line or record). Reading, building and drawing release the GIL.
"""

from __future__ import annotations

import builtins as _builtins
import datetime as _datetime
import json as _json
import os as _os
import threading as _threading
import warnings as _warnings
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, Callable, Iterator, Optional, Union

import numpy as np

from . import _strata
from ._strata import (
    FileError,
    GpuError,
    NoAdapterError,
    OptionError,
    StrataError,
    __version__,
)

__all__ = [
    "FileError",
    "GpuError",
    "Grid",
    "NoAdapterError",
    "OptionError",
    "Picture",
    "Scene",
    "Step",
    "StrataError",
    "StrataWarning",
    "__version__",
    "from_xtgeo",
    "lod_build",
    "open",
    "render",
    "render_ensemble",
    "synth",
    "view",
]

PathLike = Union[str, "_os.PathLike[str]"]

# Mesa's Vulkan device-select layer probes for a Wayland display and complains where
# there is none (a server, a Dask worker); strata picks its adapter itself. As the
# command line does, a user's own setting stands.
if "XDG_RUNTIME_DIR" not in _os.environ:
    _os.environ.setdefault("NODEVICE_SELECT", "1")


class StrataWarning(UserWarning):
    """Something reading or drawing worked around: a skipped INCLUDE, a stray corner."""


class Step:
    """One report step of a simulation: its number (SEQNUM), date and arrays."""

    def __init__(self, grid: "Grid", index: int, number: int, date, names: list[str]):
        self._grid = grid
        self._index = index
        #: Report number (SEQNUM).
        self.number: int = number
        #: Simulation date, when the restart file gives one.
        self.date: Optional[_datetime.date] = _datetime.date(*date) if date else None
        #: Names of the solution arrays (PRESSURE, SWAT, ...).
        self.names: list[str] = names

    def __getitem__(self, name: str) -> np.ma.MaskedArray:
        """Array ``name`` as a masked ``(nx, ny, nz)`` array, inactive cells masked."""
        values = self._grid._native.step_array(self._index, name)
        if values is None:
            raise KeyError(f"report step {self.number} has no array {name!r}; it has {', '.join(self.names)}")
        return self._grid._masked(values)

    def __repr__(self) -> str:
        return f"Step({self.number}, {self.date}, {self.names})"


class _Properties(Mapping):
    """A grid's static properties by name, each a masked ``(nx, ny, nz)`` array."""

    def __init__(self, grid: "Grid"):
        self._grid = grid

    def __getitem__(self, name: str) -> np.ma.MaskedArray:
        values = self._grid._native.property(name)
        if values is None:
            raise KeyError(f"{self._grid.path}: no property {name!r}; it has {', '.join(self) or 'none'}")
        return self._grid._masked(values)

    def __iter__(self) -> Iterator[str]:
        return iter(self._grid._native.property_names())

    def __len__(self) -> int:
        return len(self._grid._native.property_names())


class Grid:
    """A corner-point model: dimensions, active cells, corners, properties, results.

    Arrays come in ``(nx, ny, nz)`` order (i slowest, as xtgeo has them). Those the
    model holds (ACTNUM, COORD, ZCORN, properties, report arrays) are lent by the
    Rust model without a copy and are read-only; their ``(nx, ny, nz)`` views are
    transposes of the file-order ``(nz, ny, nx)`` arrays, so not C-contiguous.
    Corners are computed (a file holds pillars and depths), once, into an array numpy
    owns.
    """

    def __init__(self, native: "_strata._Grid"):
        self._native = native
        self._corners: Optional[np.ndarray] = None

    @property
    def dims(self) -> tuple[int, int, int]:
        """(nx, ny, nz)."""
        return self._native.dims

    @property
    def path(self) -> str:
        """The file read (or the name a grid made in memory was given)."""
        return _os.fspath(self._native.source[0])

    @property
    def warnings(self) -> list[str]:
        """What reading skipped or found suspicious, one line each, naming the file."""
        return self._native.warnings

    @property
    def units(self) -> str:
        """Length unit of the coordinates (METRES, FEET, CM)."""
        return self._native.units

    @property
    def mapaxes(self) -> Optional[tuple[float, ...]]:
        """MAPAXES when the file had them (corners already have them applied)."""
        m = self._native.mapaxes
        return tuple(m) if m is not None else None

    @property
    def active(self) -> np.ndarray:
        """Whether each cell is active, bool ``(nx, ny, nz)`` (a view of ACTNUM)."""
        return self._native.actnum().T

    @property
    def active_count(self) -> int:
        """Number of active cells."""
        return self._native.active_count

    @property
    def coord(self) -> np.ndarray:
        """COORD as the file has it: ``(ny + 1, nx + 1, 6)`` pillars, before MAPAXES."""
        return self._native.coord()

    @property
    def zcorn(self) -> np.ndarray:
        """ZCORN as the file has it: ``(2 nz, 2 ny, 2 nx)`` corner depths."""
        return self._native.zcorn()

    @property
    def corners(self) -> np.ndarray:
        """Corners in map coordinates (x, y, depth): ``(nx, ny, nz, 8, 3)`` float64.

        Corner order as Eclipse and xtgeo number them: top face (i, j), (i+1, j),
        (i, j+1), (i+1, j+1), then the bottom face the same way.
        """
        if self._corners is None:
            self._corners = self._native.corners()
            self._corners.flags.writeable = False
        return self._corners

    @property
    def properties(self) -> Mapping[str, np.ma.MaskedArray]:
        """Static properties by name (PORO, PERMX ...), masked where inactive or undefined."""
        return _Properties(self)

    @property
    def steps(self) -> list[Step]:
        """Report steps of the simulation (UNRST or ``.Xnnnn`` beside an EGRID)."""
        return [Step(self, n, *s) for n, s in enumerate(self._native.steps())]

    def cell(self, i: int, j: int, k: int) -> dict[str, Any]:
        """Cell (i, j, k), 1-based, as ``strata info --cell I,J,K --json`` gives it.

        Keys: file, cell, active, corner_order, corners (8 x (x, y, depth)) and values
        (static properties, then the last report step's arrays as ``NAME@STEP``;
        None where undefined).
        """
        info = _json.loads(self._native.cell_json(i, j, k))
        info["values"] = dict(info["values"])
        return info

    def save(self, path: PathLike) -> None:
        """Writes the grid and its static properties: EGRID for a ``.egrid`` name, else GRDECL."""
        self._native.save(_os.fspath(path))

    def to_xtgeo(self):
        """An ``xtgeo.Grid`` with the same corners (MAPAXES applied) and active cells."""
        from . import _xtgeo

        return _xtgeo.to_xtgeo(self)

    def render(self, scene: Optional["Scene"] = None, **fields) -> "Picture":
        """``strata.render(self, scene, **fields)``."""
        return render(self, scene, **fields)

    def _repr_png_(self) -> bytes:
        """A small picture of the model (layers and sides, default colouring) for Jupyter."""
        return render(self, Scene(sides=True, size=[480, 360]))._repr_png_()

    def __repr__(self) -> str:
        nx, ny, nz = self.dims
        return f"<strata.Grid {self.path}: {nx} x {ny} x {nz}, {self.active_count} active>"

    def _masked(self, values: np.ndarray) -> np.ma.MaskedArray:
        """File-order ``values`` as ``(nx, ny, nz)``, masked where inactive or NaN."""
        values = values.T
        return np.ma.MaskedArray(values, mask=~self.active | np.isnan(values))


def open(path: PathLike, props: Sequence[PathLike] = (), grid_only: bool = False) -> Grid:
    """Reads a model as the command line does: GRDECL, DATA or EGRID.

    An EGRID's INIT and restart files (UNRST or ``.Xnnnn``) beside it are read too.
    ``props`` are GRDECL decks of per-cell properties to add (e.g. PORO beside an
    EGRID); ``grid_only`` reads geometry and ACTNUM only, and lets a deck go on past
    missing INCLUDE files (each named in :attr:`Grid.warnings`).

    Raises :class:`FileError` naming the file, keyword and line or record.
    """
    native = _strata._Grid.open(_os.fspath(path), [_os.fspath(p) for p in props], grid_only)
    grid = Grid(native)
    for warning in grid.warnings:
        _warnings.warn(warning, StrataWarning, stacklevel=2)
    return grid


def synth(nx: int = 60, ny: int = 40, nz: int = 10, faults: int = 4, seed: int = 1) -> Grid:
    """A generated faulted model with PORO and PERMX, as ``strata synth`` writes it;
    the same seed gives the same model. :meth:`Grid.save` writes it."""
    return Grid(_strata._Grid.synth(nx, ny, nz, faults, seed))


def from_xtgeo(grid, props: Union[Iterable[Any], Mapping[str, Any], None] = None) -> Grid:
    """A :class:`Grid` of an ``xtgeo.Grid``, with the same corners and active cells.

    ``props``: ``xtgeo.GridProperty`` objects, or a mapping of names to ``(nx, ny,
    nz)`` arrays; ``None`` takes the grid's own properties.
    """
    from . import _xtgeo

    return _xtgeo.from_xtgeo(grid, props)


def _plain(value):
    """``value`` as JSON takes it: paths as strings, tuples and arrays as lists."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (_os.PathLike,)):
        return _os.fspath(value)
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _merge(base: dict, changes: Mapping) -> dict:
    """``base`` with ``changes``; a mapping changes the fields it names, not the rest."""
    out = dict(base)
    for key, value in changes.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


class Scene:
    """Everything a picture depends on: the JSON scene of ``strata render --save-scene``.

    Keyword arguments are its fields (``layers``, ``i``, ``j``, ``inactive``,
    ``sides``, ``colour``, ``wire``, ``isolines``, ``grid_lines``, ``camera``,
    ``size``, ``lod``, ``part_cells``, and any the library adds), checked by the
    library's ``Scene``: a wrong one raises :class:`OptionError` naming the field.
    Nested fields are dicts (``camera={"azimuth": 90}``); a field left out takes the
    command line's default. ``model`` may be a path. The model is usually given to
    :func:`render` instead.
    """

    def __init__(self, **fields):
        if isinstance(fields.get("model"), (str, _os.PathLike)):
            fields["model"] = {"path": fields["model"]}
        self._fields: dict = _json.loads(_strata.check_scene(_json.dumps(_plain(fields))))

    @classmethod
    def from_json(cls, text: str) -> "Scene":
        """A scene from JSON (what ``--save-scene`` writes)."""
        return cls(**_json.loads(text))

    @classmethod
    def load(cls, path: PathLike) -> "Scene":
        """A scene from a JSON file (what ``--save-scene`` writes)."""
        with _builtins.open(path, encoding="utf-8") as f:
            return cls.from_json(f.read())

    def to_json(self) -> str:
        """The scene as JSON, every field written (``strata render --scene`` reads it)."""
        return _json.dumps(self._fields, indent=2)

    def to_dict(self) -> dict:
        """The fields, defaults filled in."""
        return _json.loads(_json.dumps(self._fields))

    def replace(self, **fields) -> "Scene":
        """A new scene with ``fields`` changed; a dict changes only the keys it names."""
        if isinstance(fields.get("model"), (str, _os.PathLike)):
            fields["model"] = {"path": fields["model"]}
        return Scene(**_merge(self._fields, _plain(fields)))

    def __getattr__(self, name: str):
        try:
            return self.__dict__["_fields"][name]
        except KeyError:
            raise AttributeError(f"a scene has no field {name!r}") from None

    def __eq__(self, other) -> bool:
        return isinstance(other, Scene) and self._fields == other._fields

    def __repr__(self) -> str:
        return f"strata.Scene(**{self._fields!r})"


class Picture(np.ndarray):
    """A rendered picture: an ``(H, W, 4)`` uint8 RGBA numpy array that shows itself
    in Jupyter and saves as PNG. ``notes`` holds what the engine said about it."""

    notes: list[tuple[str, str]]

    def __new__(cls, pixels: np.ndarray, notes: Sequence[tuple[str, str]] = ()):
        picture = np.asarray(pixels).view(cls)
        picture.notes = list(notes)
        return picture

    def __array_finalize__(self, obj) -> None:
        self.notes = getattr(obj, "notes", [])

    def _repr_png_(self) -> Optional[bytes]:
        if self.ndim != 3 or self.shape[2] != 4 or self.dtype != np.uint8:
            return None
        return _strata.png(np.ascontiguousarray(self.view(np.ndarray)))

    def save(self, path: PathLike) -> None:
        """Writes the picture as PNG."""
        data = self._repr_png_()
        if data is None:
            raise OptionError(f"{_os.fspath(path)}: only an (H, W, 4) uint8 picture is saved as PNG")
        with _builtins.open(path, "wb") as f:
            f.write(data)


_ENGINE: Optional["_strata._Engine"] = None
_ENGINE_LOCK = _threading.Lock()


def _engine() -> "_strata._Engine":
    """This process's engine: it keeps what it built for the next picture, and its GPU
    device, so a new camera on the same model draws without reading or building."""
    global _ENGINE
    with _ENGINE_LOCK:
        if _ENGINE is None:
            _ENGINE = _strata._Engine()
        return _ENGINE


_HIERARCHY_MAGIC = b"STRATLOD"


def _scene_for(what, scene: Optional[Scene], fields: dict) -> tuple[Scene, Optional[Grid]]:
    """The scene to draw ``what`` (a Grid, a model path, a ``.lod`` file, or None)."""
    if scene is None:
        scene = Scene(**fields)
    elif fields:
        scene = scene.replace(**fields)
    if what is None or isinstance(what, Grid):
        return scene, what
    path = _os.fspath(what)
    try:
        with _builtins.open(path, "rb") as f:
            is_hierarchy = f.read(len(_HIERARCHY_MAGIC)) == _HIERARCHY_MAGIC
    except OSError:
        is_hierarchy = False  # the engine names the file and why it cannot be read
    if is_hierarchy:
        lod = scene.lod if scene.lod.get("kind") == "hierarchy" else {"kind": "hierarchy"}
        return Scene(**_merge(scene._fields, {"model": None, "lod": {**lod, "file": path}})), None
    model = scene.model or {}
    same = model.get("path") == path
    return scene.replace(model={"path": path, "props": model.get("props", []) if same else [],
                                "grid_only": model.get("grid_only", False) if same else False}), None


def render(what: Union[Grid, PathLike, None] = None, scene: Optional[Scene] = None, **fields) -> Picture:
    """Draws ``what`` (a :class:`Grid`, a model file, a ``.lod`` hierarchy, or the
    scene's own model when None) as ``scene`` says, with ``fields`` changed.

    Returns a :class:`Picture`, ``(H, W, 4)`` uint8. This process's engine keeps what it
    built: drawing the same grid again with another camera or line style reads and
    builds nothing. Warnings (a stray corner ...) are issued as :class:`StrataWarning`.
    """
    scene, grid = _scene_for(what, scene, fields)
    pixels, notes = _engine().render(scene.to_json(), grid._native if grid else None)
    for kind, text in notes:
        if kind == "warning":
            _warnings.warn(text, StrataWarning, stacklevel=2)
    return Picture(pixels, notes)


def view(what: Union[Grid, PathLike, None] = None, scene: Optional[Scene] = None, *,
         script: Optional[PathLike] = None, size: tuple[int, int] = (1280, 800),
         **fields) -> dict:
    """Opens the interactive window (``strata view``) on ``what`` as ``scene`` says,
    with ``fields`` changed, and blocks until it is closed (or ``script`` ends: the
    commands of ``strata view --script``).

    ``what``: a :class:`Grid` (one made in memory is written to a temporary GRDECL
    deck first), a model file, a ``.lod`` hierarchy, or None for the scene's own model.
    Needs a display (X11 or Wayland); one window per process. Returns the frame
    statistics: ``frames``, ``median_ms``, ``worst_ms``.
    """
    temporary = None
    try:
        if isinstance(what, Grid):
            if not _os.path.isfile(what.path):
                import tempfile

                temporary = tempfile.TemporaryDirectory()
                deck = _os.path.join(temporary.name, "grid.grdecl")
                what.save(deck)
                what = deck
            else:
                what = what.path
        scene, _ = _scene_for(what, scene, fields)
        script = _os.fspath(script) if script is not None else None
        frames, median, worst = _strata.view(scene.to_json(), script, tuple(size))
        return {"frames": frames, "median_ms": median, "worst_ms": worst}
    finally:
        if temporary is not None:
            temporary.cleanup()


def _render_in_worker(path: str, scene_json: str) -> tuple[np.ndarray, list]:
    """One realization, drawn by the engine of the process it runs in (a Dask worker's)."""
    scene, _ = _scene_for(path, Scene.from_json(scene_json), {})
    pixels, notes = _engine().render(scene.to_json(), None)
    return pixels, notes


def render_ensemble(paths: Sequence[PathLike], scene: Optional[Scene] = None, client=None,
                    **fields) -> list[Picture]:
    """One picture per realization in ``paths``, all drawn with ``scene``.

    Without ``client`` they are drawn here, one after another, by this process's
    engine. With a Dask ``distributed.Client`` they are spread over the cluster's
    workers, each keeping its own engine (and GPU device) from one realization to the
    next; the pictures come back in the order of ``paths``.
    """
    scene = scene.replace(**fields) if scene is not None else Scene(**fields)
    paths = [_os.fspath(p) for p in paths]
    if client is None:
        return [render(p, scene) for p in paths]
    text = scene.to_json()
    futures = client.map(_render_in_worker, paths, scene_json=text, pure=False)
    return [Picture(pixels, notes) for pixels, notes in client.gather(futures)]


def _tqdm_bar(path: str) -> Optional[Callable[[int, int], None]]:
    """A tqdm bar (the notebook's in Jupyter) fed ``(done, total)``; None without tqdm."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    bar = tqdm(total=0, desc=f"lod build {_os.path.basename(path)}", unit="tile")

    def update(done: int, total: int) -> None:
        if bar.total != total:
            bar.total = total
        bar.update(done - bar.n)
        if done >= total > 0:
            bar.close()

    return update


def lod_build(path: PathLike, output: PathLike, props: Sequence[PathLike] = (),
              grid_only: bool = False, property: Optional[str] = None, no_property: bool = False,
              tile: int = 64, zscale: float = 5.0,
              progress: Union[bool, Callable[[int, int], None]] = True) -> dict[str, Any]:
    """Builds a level-of-detail hierarchy of every layer, as ``strata lod build`` does.

    ``property`` is stored as the vertices' scalar (PORO when the model has it, unless
    ``no_property``). ``progress``: True shows a tqdm bar (the notebook's in Jupyter)
    when tqdm is installed; a callable is called with ``(done, total)`` work units.
    Returns the build's report. :func:`render` draws the file.
    """
    path, output = _os.fspath(path), _os.fspath(output)
    props = [_os.fspath(p) for p in props]
    for source in [path, *props]:
        if _os.path.exists(output) and _os.path.exists(source) and _os.path.samefile(output, source):
            raise FileError(f"{output}: is {source}, which this command reads; choose another output")
    callback = _tqdm_bar(path) if progress is True else (progress or None)
    layers, nodes, levels, triangles, stored, size, seconds = _strata.lod_build(
        path, output, props, grid_only, property, no_property, tile, zscale, callback)
    return {"layers": layers, "nodes": nodes, "levels": levels + 1, "input_triangles": triangles,
            "stored_triangles": stored, "bytes": size, "seconds": seconds}
