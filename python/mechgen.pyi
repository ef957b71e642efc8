"""Planar linkage kinematics from loop equations: the generated solvers of the compiled-in
mechanism file and the generic engine for any file, sweeps and batches to numpy."""

from os import PathLike
from typing import Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

class Mechanism:
    """One mechanism: its generated solvers (compiled in) or the generic engine (a loaded file)."""

    @property
    def name(self) -> str: ...
    @property
    def params(self) -> dict[str, float]:
        """The base params, name -> value (derived params follow from them)."""
    @property
    def inputs(self) -> list[str]: ...
    @property
    def unknowns(self) -> list[str]: ...
    @property
    def points(self) -> list[str]: ...
    @property
    def engine(self) -> str:
        """"generated" or "generic"."""
    def sweep(
        self,
        start: Optional[float] = None,
        stop: Optional[float] = None,
        step: Optional[float] = None,
        rate: float = 1.0,
        input: Optional[str] = None,
        set: Optional[Mapping[str, float]] = None,
        params: Optional[Mapping[str, float]] = None,
    ) -> dict[str, np.ndarray]:
        """One sweep as `mechgen sweep` sweeps it: CSV column -> 1-D array (status: an object
        array of shared str)."""
    def batch(
        self,
        params: Mapping[str, Union[npt.ArrayLike, Sequence[float]]],
        start: Optional[float] = None,
        stop: Optional[float] = None,
        step: Optional[float] = None,
        rate: float = 1.0,
        input: Optional[str] = None,
        set: Optional[Mapping[str, float]] = None,
        threads: Optional[int] = None,
        out: Optional[dict[str, np.ndarray]] = None,
    ) -> dict[str, np.ndarray]:
        """Every param set swept on `threads` worker threads (default every core), the GIL
        released: CSV column -> 2-D array (sets, rows). MemoryError (naming the size) before
        anything is allocated when the result cannot fit; Ctrl-C raises KeyboardInterrupt.
        `out`: the dict an earlier batch of as many sets and rows returned; its number arrays
        are written in place and it is returned (its `status` a new array)."""
    def sensitivity(
        self,
        start: Optional[float] = None,
        stop: Optional[float] = None,
        step: Optional[float] = None,
        rate: float = 1.0,
        input: Optional[str] = None,
        set: Optional[Mapping[str, float]] = None,
        params: Optional[Mapping[str, float]] = None,
    ) -> dict[str, np.ndarray]:
        """d(output)/d(param) along a sweep, as `mechgen sensitivity --csv`: column `u/p` per
        unknown u and param p, `P_x/p`, `P_y/p` per point, then status."""
    def dynamics(
        self,
        start: Optional[float] = None,
        stop: Optional[float] = None,
        step: Optional[float] = None,
        rate: float = 1.0,
        acc: float = 0.0,
        loads: Optional[Sequence[tuple]] = None,
        input: Optional[str] = None,
        set: Optional[Mapping[str, float]] = None,
        params: Optional[Mapping[str, float]] = None,
    ) -> dict[str, np.ndarray]:
        """Inverse dynamics along a sweep (a mechanism with bodies), as `mechgen dynamics --csv`:
        the input, every unknown, effort_X, inertia_X_X, kinetic_energy, potential_energy,
        shaking_fx, shaking_fy, shaking_moment, status. `loads`: (point, fx, fy) or
        (point, fx, fy, (a, b)) acting while the angle input lies in [a, b] degrees."""
    def simulate(
        self,
        time: float,
        dt: float,
        torque: float = 0.0,
        rate: float = 0.0,
        loads: Optional[Sequence[tuple]] = None,
        input: Optional[str] = None,
        set: Optional[Mapping[str, float]] = None,
        params: Optional[Mapping[str, float]] = None,
    ) -> dict[str, np.ndarray]:
        """Forward dynamics from the start configuration (a mechanism with bodies), as `mechgen
        simulate --csv`: t, the input, X_vel, X_acc, every unknown, kinetic_energy,
        potential_energy, status; a row every dt to time (a dead point ends it). Loads as for
        `dynamics`: (point, fx, fy), or (point, fx, fy, (a, b)) acting over [a, b] degrees; where
        the forces on both sides of such a range's edge push into it, the input rests there and
        the rows' status is "at-load-edge"."""

    def __reduce__(self) -> tuple: ...

def mechanisms() -> dict[str, Mechanism]:
    """The compiled-in mechanisms, name -> Mechanism (generated solvers), in file order."""

def load(path: Union[str, PathLike[str]], engine: Optional[str] = None) -> dict[str, Mechanism]:
    """Every mechanism of a file, in file order, on the generic engine (`engine="generic"`);
    ValueError with every diagnostic."""
