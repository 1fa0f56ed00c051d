"""Grids to and from xtgeo, whose arrays hold the same model in another layout.

xtgeo keeps pillars as ``coordsv`` ``(nx + 1, ny + 1, 6)`` in map coordinates and
depths as ``zcornsv`` ``(nx + 1, ny + 1, nz + 1, 4)``: at each pillar and layer
boundary, the depth of the four cells around it, south-west, south-east, north-west,
north-east. Eclipse's ZCORN holds 8 depths per cell. Cell (i, j, k)'s corner with
offsets (di, dj, dk) lies on pillar (i + di, j + dj), where the cell is the
pillar's ``(1 - di) + 2 (1 - dj)``-th neighbour. xtgeo has one depth per boundary,
so a gap between a cell's bottom and the top of the cell below cannot be kept: as
xtgeo's own reader does, the top of the lower cell wins.
"""

from __future__ import annotations

import numpy as np

from . import Grid, _strata


def _neighbour(di: int, dj: int) -> int:
    return (1 - di) + 2 * (1 - dj)


def from_xtgeo(xgrid, props=None) -> Grid:
    """See :func:`strata.from_xtgeo`."""
    xgrid._set_xtgformat2()  # xtgeo's current layout, which its constructor takes
    coordsv = np.asarray(xgrid._coordsv, dtype=np.float64)
    zcornsv = np.asarray(xgrid._zcornsv, dtype=np.float32)
    nx, ny, nz = (int(n) for n in xgrid.dimensions)
    zcorn = np.empty((2 * nz, 2 * ny, 2 * nx), dtype=np.float32)
    for dk in (0, 1):
        for dj in (0, 1):
            for di in (0, 1):
                part = zcornsv[di:di + nx, dj:dj + ny, dk:dk + nz, _neighbour(di, dj)]
                zcorn[dk::2, dj::2, di::2] = part.transpose(2, 1, 0)
    coord = np.ascontiguousarray(coordsv.transpose(1, 0, 2))
    actnum = np.ascontiguousarray(np.asarray(xgrid._actnumsv).transpose(2, 1, 0) != 0)
    if props is None:
        props = list(xgrid.props or [])
    if hasattr(props, "items"):
        named = dict(props.items())
    else:
        named = {p.name: p.values for p in props}
    properties = {}
    for name, values in named.items():
        values = np.ma.filled(np.ma.asarray(values, dtype=np.float32), np.nan)
        if values.shape != (nx, ny, nz):
            from . import OptionError

            raise OptionError(f"property {name}: shape {values.shape}, the grid is ({nx}, {ny}, {nz})")
        properties[name] = np.ascontiguousarray(values.transpose(2, 1, 0))
    name = getattr(xgrid, "name", None) or "xtgeo grid"
    return Grid(_strata._Grid.from_arrays((nx, ny, nz), coord, zcorn, actnum, properties, str(name)))


def to_xtgeo(grid: Grid):
    """See :meth:`strata.Grid.to_xtgeo`."""
    import xtgeo

    nx, ny, nz = grid.dims
    zcorn = grid.zcorn
    zcornsv = np.full((nx + 1, ny + 1, nz + 1, 4), np.nan, dtype=np.float32)
    # Bottoms first, so that the top of the cell below wins where they differ.
    for dk in (1, 0):
        for dj in (0, 1):
            for di in (0, 1):
                part = zcorn[dk::2, dj::2, di::2].transpose(2, 1, 0)
                zcornsv[di:di + nx, dj:dj + ny, dk:dk + nz, _neighbour(di, dj)] = part
    # Pillars on the outline have no cell on one side: those depths repeat a
    # neighbour's, as xtgeo's readers fill them (any present value serves; the one
    # nearest in the SW, SE, NW, NE order).
    missing = np.isnan(zcornsv)
    if missing.any():
        for n in range(4):
            for other in (n ^ 1, n ^ 2, n ^ 3):
                fill = missing[..., n] & ~np.isnan(zcornsv[..., other])
                zcornsv[..., n][fill] = zcornsv[..., other][fill]
                missing[..., n] &= ~fill
    coordsv = np.ascontiguousarray(grid._native.map_coord().transpose(1, 0, 2))
    actnumsv = np.ascontiguousarray(grid.active.astype(np.int32))
    xgrid = xtgeo.Grid(coordsv, zcornsv, actnumsv, name=str(grid.path))
    for name, values in grid.properties.items():
        xgrid.append_prop(xtgeo.GridProperty(xgrid, values=values.astype(np.float64), name=name))
    return xgrid
