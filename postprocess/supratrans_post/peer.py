"""SciPy peer of supratrans: the paper's chain integrated with `scipy.integrate.solve_ivp` (DOP853, RK45), as a
scientist would without our code; timed and scored against the reference of a `work_precision` file.

    python3 postprocess/peer_scipy.py out/work_precision.h5                 # DOP853 and RK45, tol 1e-3..1e-12
    python3 postprocess/peer_scipy.py out/work_precision.h5 --check         # model check only (tight tolerance)
    python3 postprocess/peer_scipy.py out/work_precision.h5 -o peer.json --methods DOP853 --tols 1e-4 1e-8

The model is the one of `src/numerics/supratrans_mol.f90` (`chain_rhs`), as a first-order system of size 2N + 1, with
every parameter read from the file's `/parameters` attributes (nothing re-typed here):

    u_n' = v_n,
    v_n' = c^2 (u_{n+1} - 2 u_n + u_{n-1}) + beta (v_{n+1} - 2 v_n + v_{n-1}) - alpha_n v_n - m^2 u_n - V'(u_n),
    W'   = c^2 (u_0 - u_1) psi' + beta (psi' - v_1) psi'        (the injected energy, integrated with the chain),

n = 1..N, u_0 = psi(t) = A r(t) sin(Omega t), v_0 = psi'(t), r(t) = min(t/ramp_time, 1), u_{N+1} = v_{N+1} = 0,
alpha_n = gamma + gamma'(n), gamma'(n) = kappa [1 + tanh((2n - N0 - N)/(2 sigma))] for N0 < n <= N (the smooth
absorber; docs/method.md, notes on the paper). V'(u) = sin u (sine-Gordon), u - u^3/6 + u^5/120 (Klein-Gordon) or
sin u + 2 eta sin 2u (double sine-Gordon, `eta` from /parameters; 0 in files written before the key existed).
W is a component of the state, so its accuracy is the integrator's own (no quadrature on top).

The drive has a kink at t = ramp_time (psi' jumps by -A sin(Omega ramp_time)/ramp_time). An adaptive method
stepping over it loses its order there and spends many rejected steps finding it; a careful user integrates in
two segments, [0, ramp_time] and [ramp_time, T], restarting at the kink. That is done here; our fixed-step
methods get the same by landing a step on it (every dt of the scene divides ramp_time).

Tolerances: `rtol = tol`, `atol = tol * scale` per component, scale = A for u, A Omega for v (the drive's
amplitude and velocity) and A^2 c^2 for W (the injected power's scale times unit time). Timing: `time.perf_counter`
around the two `solve_ivp` calls with `t_eval=None` and no dense output, the median of `repeats` (5) runs; a
separate, untimed run with `t_eval` over the last drive period gives u at the probe for the error in u.
Errors, as the Fortran scene measures them: the injected energy at T against `/reference/injected`, relative;
u at the probe site (`/scene probe_site`) at T against `/reference/u_final`, and the largest |u - u_ref| over the
last drive period against this module's own tightest DOP853 run (the file keeps only u at T of its reference;
the tight run is checked against it).

A file that cannot be used gives the one line `error: <file>: <what is wrong>` and exit status 2.
"""
from __future__ import annotations

import json
import math
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from . import cli
from .reader import PlotError, Scene, open_scene, output_path

#: Tolerances of the peer: 1e-3 .. 1e-12.
DEFAULT_TOLS = [10.0 ** -k for k in range(3, 13)]
#: SciPy methods compared.
DEFAULT_METHODS = ["DOP853", "RK45"]
#: The model check: at this tolerance DOP853 must reproduce the reference's injected energy to CHECK_LIMIT.
CHECK_TOL = 1e-13
CHECK_LIMIT = 1e-9


# ------------------------------------------------------------------------------------------------ reading


#: Parameters of the model that `/parameters` may lack (files written before the key existed), with their value then.
OPTIONAL_PARAMETERS = {"eta": 0.0}

#: Parameters the model needs from `/parameters`.
MODEL_PARAMETERS = ("potential", "c", "beta", "gamma", "m2", "n", "n0", "kappa", "sigma", "omega", "ramp_time",
                    "t_final")


def read_work_precision(path: Any) -> Scene:
    """The `work_precision` file (see `reader.open_scene`: its datasets and shapes checked), with the model's
    parameters."""
    w = open_scene(path, "work_precision")
    missing = [k for k in MODEL_PARAMETERS if k not in w.params]
    if missing:
        raise PlotError(w.path, f"/parameters lacks {', '.join(missing)}")
    return w


# ------------------------------------------------------------------------------------------------ the model


@dataclass
class Chain:
    """The chain of the paper (eq. 1 on N sites, Sec. 3.1) with its drive, from a file's `/parameters`."""

    potential: str
    c: float
    beta: float
    gamma: float
    m2: float
    n: int
    n0: int
    kappa: float
    sigma: float
    omega: float
    ramp_time: float
    t_final: float
    eta: float = 0.0
    alpha: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.potential not in ("sine-gordon", "klein-gordon", "double-sine-gordon"):
            raise ValueError(f"unknown potential '{self.potential}'")
        self.alpha = self.gamma + self.absorber()

    @classmethod
    def from_params(cls, params: dict, **override: Any) -> "Chain":
        """The chain of a file's `/parameters` (MODEL_PARAMETERS), some of them replaced by `override`."""
        kw = {k: params[k] for k in MODEL_PARAMETERS}
        kw.update({k: params.get(k, v) for k, v in OPTIONAL_PARAMETERS.items()})
        kw.update(override)
        kw["potential"] = str(kw["potential"])
        for k in ("c", "beta", "gamma", "m2", "kappa", "sigma", "omega", "ramp_time", "t_final", "eta"):
            kw[k] = float(kw[k])
        kw["n"], kw["n0"] = int(kw["n"]), int(kw["n0"])
        return cls(**kw)

    def absorber(self) -> np.ndarray:
        """gamma'(n), n = 1..N: kappa [1 + tanh((2n - N0 - N)/(2 sigma))] for N0 < n <= N, else 0."""
        n = np.arange(1, self.n + 1, dtype=float)
        g = self.kappa * (1.0 + np.tanh((2.0 * n - self.n0 - self.n) / (2.0 * self.sigma)))
        return np.where(n > self.n0, g, 0.0)

    def force(self, u: np.ndarray) -> np.ndarray:
        """V'(u)."""
        if self.potential == "sine-gordon":
            return np.sin(u)
        if self.potential == "double-sine-gordon":
            return np.sin(u) + 2.0 * self.eta * np.sin(2.0 * u)
        u2 = u * u
        return u * (1.0 + u2 * (-1.0 / 6.0 + u2 / 120.0))

    def segments(self) -> list[tuple[float, float, bool]]:
        """[(t0, t1, ramping)]: [0, ramp_time] with the ramp, [ramp_time, T] without (one piece when the kink is
        not inside (0, T))."""
        tr, tf = self.ramp_time, self.t_final
        if 0.0 < tr < tf:
            return [(0.0, tr, True), (tr, tf, False)]
        return [(0.0, tf, tr >= tf)]

    def drive(self, amplitude: float, ramping: bool) -> Callable[[float], tuple[float, float]]:
        """(psi(t), psi'(t)) on a segment: the ramp r = t/ramp_time, r' = 1/ramp_time while `ramping`, else 1, 0."""
        a, w = float(amplitude), self.omega
        if ramping and self.ramp_time > 0.0:
            s = a / self.ramp_time

            def psi(t):
                return s * t * math.sin(w * t), s * (math.sin(w * t) + t * w * math.cos(w * t))
        else:
            def psi(t):
                return a * math.sin(w * t), a * w * math.cos(w * t)
        return psi

    def rhs(self, amplitude: float, ramping: bool) -> Callable[[float, np.ndarray], np.ndarray]:
        """f(t, y) of the system y = (u_1..u_N, v_1..v_N, W) on one segment, vectorised over the sites."""
        n, c2, beta, m2 = self.n, self.c ** 2, self.beta, self.m2
        alpha = self.alpha
        psi = self.drive(amplitude, ramping)
        force = self.force
        up = np.zeros(n + 2)  # u_0 .. u_{N+1}, u_{N+1} = 0
        vp = np.zeros(n + 2)

        def f(t, y):
            p, dp = psi(t)
            u = y[:n]
            v = y[n:2 * n]
            up[0] = p
            up[1:n + 1] = u
            dydt = np.empty_like(y)
            dydt[:n] = v
            acc = c2 * (up[2:] - 2.0 * u + up[:-2]) - alpha * v - force(u)
            if m2 != 0.0:
                acc -= m2 * u
            if beta != 0.0:
                vp[0] = dp
                vp[1:n + 1] = v
                acc += beta * (vp[2:] - 2.0 * v + vp[:-2])
            dydt[n:2 * n] = acc
            dydt[2 * n] = c2 * (p - u[0]) * dp + beta * (dp - v[0]) * dp
            return dydt

        return f

    def scales(self, amplitude: float) -> np.ndarray:
        """Per-component scale of the absolute tolerance: A (u), A Omega (v), A^2 c^2 (W)."""
        a = float(amplitude)
        s = np.empty(2 * self.n + 1)
        s[:self.n] = a
        s[self.n:2 * self.n] = a * self.omega
        s[2 * self.n] = a * a * self.c ** 2
        return s


# ------------------------------------------------------------------------------------------------ solving


@dataclass
class Solve:
    """One integration over [0, T]."""

    ok: bool
    message: str
    injected: float
    u_final: np.ndarray  # u_1..u_N at T
    nfev: int
    steps: int  # accepted steps
    seconds: float
    window_t: np.ndarray | None = None
    window_u: np.ndarray | None = None  # u at the probe at window_t


def solve(chain: Chain, amplitude: float, method: str, tol: float, probe: int | None = None,
          window: float | None = None) -> Solve:
    """Integrate the chain at rest at t = 0 to T, segment by segment. With `probe` (site, 1-based) and `window`
    (length), u at the probe is also returned at the times of the last `window` of the run at which the
    scipy dense output is evaluated (t_eval: 200 points); otherwise `t_eval=None`, no dense output."""
    from scipy.integrate import solve_ivp  # noqa: PLC0415

    y = np.zeros(2 * chain.n + 1)
    atol = tol * chain.scales(amplitude)
    nfev = steps = 0
    wt = wu = None
    t_start = time.perf_counter()
    for t0, t1, ramping in chain.segments():
        t_eval = None
        if probe is not None and window is not None and t1 == chain.t_final:
            lo = max(t0, t1 - window)
            t_eval = np.linspace(lo, t1, 201)
        sol = solve_ivp(chain.rhs(amplitude, ramping), (t0, t1), y, method=method, rtol=tol, atol=atol,
                        t_eval=t_eval)
        nfev += int(sol.nfev)
        steps += max(sol.t.size - 1, 0) if t_eval is None else 0
        if sol.status != 0 or not np.all(np.isfinite(sol.y[:, -1])):
            return Solve(False, sol.message, math.nan, np.full(chain.n, math.nan), nfev, steps,
                         time.perf_counter() - t_start)
        y = sol.y[:, -1].copy()
        if t_eval is not None:
            wt, wu = sol.t, sol.y[probe - 1]
    seconds = time.perf_counter() - t_start
    return Solve(True, "", float(y[2 * chain.n]), y[:chain.n].copy(), nfev, steps, seconds, wt, wu)


def timed(chain: Chain, amplitude: float, method: str, tol: float, repeats: int = 5,
          budget: float | None = None) -> tuple[float, Solve, list[float]]:
    """Median wall time of `repeats` solves, the last solve, and all the times. With `budget` (seconds), the
    repeats stop once they have taken that long in all, after at least three."""
    times, last = [], None
    for _ in range(max(1, repeats)):
        last = solve(chain, amplitude, method, tol)
        times.append(last.seconds)
        if not last.ok or (budget is not None and len(times) >= 3 and sum(times) > budget):
            break
    return statistics.median(times), last, times


def reference_window(chain: Chain, amplitude: float, probe: int, window: float) -> Solve:
    """The peer's own tight reference of u at the probe over the last drive period (DOP853 at CHECK_TOL)."""
    return solve(chain, amplitude, "DOP853", CHECK_TOL, probe=probe, window=window)


def problem(w: Scene) -> tuple:
    """(chain, amplitudes, reference injected, reference u at T, probe site, window) of a work_precision file."""
    chain = Chain.from_params(w.params)
    scene = w.groups.get("scene", {})
    probe = int(scene.get("probe_site", 60))
    probe = max(1, min(probe, chain.n))
    window = float(scene.get("error_window", 2.0 * math.pi / chain.omega))
    d = w.data
    return chain, np.asarray(d["amplitude"], float), np.asarray(d["reference/injected"], float), \
        np.asarray(d["reference/u_final"], float), probe, window


def solve_cost(method: str, tol: float) -> float:
    """The expected seconds of one solve of the paper's chain (N = 200, T = 200), for the time left of the progress
    lines (only its ratios matter): an adaptive method of order p takes steps ~ tol^(-1/p) (DOP853 8, RK45 5, RK23
    3) above a floor, fitted to the peer's points of 2026-11-29 (0.2 s at 1e-3, 1 s and 6 s at 1e-12)."""
    return 0.12 + 0.024 * tol ** (-1.0 / {"DOP853": 8, "RK45": 5, "RK23": 3}.get(method, 5))


def point_cost(method: str, tol: float, repeats: int, budget: float) -> float:
    """The expected seconds of one point: its untimed solve and its timed repeats (at least three, fewer than
    `repeats` once they pass `budget`)."""
    one = solve_cost(method, tol)
    return one * (1 + min(max(1, repeats), max(3, math.ceil(budget / one))))


def check_model(w: Scene, log: Callable = print,
                progress: cli.Progress | None = None) -> tuple[list[dict], list[Solve]]:
    """The model check: DOP853 at CHECK_TOL against the file's reference, per amplitude. Returns a list of dicts
    (amplitude, injected, reference, relative error, u at T error, passed) and the reference windows; one step of
    `progress` per amplitude."""
    chain, amps, e_ref, u_ref, probe, window = problem(w)
    out, refs = [], []
    for ia, a in enumerate(amps):
        r = reference_window(chain, a, probe, window)
        rel = abs(r.injected - e_ref[ia]) / abs(e_ref[ia])
        du = abs(r.u_final[probe - 1] - u_ref[ia])
        ok = r.ok and rel <= CHECK_LIMIT
        out.append({"amplitude": float(a), "injected": r.injected, "reference": float(e_ref[ia]),
                    "relative_error": rel, "error_u_final": du, "passed": bool(ok), "seconds": r.seconds})
        refs.append(r)
        log(f"model check A = {a:g}: DOP853 at tol {CHECK_TOL:g}: injected {r.injected:.12g}, reference "
            f"{e_ref[ia]:.12g}, relative difference {rel:.2e} ({'ok' if ok else 'MISMATCH'}, limit "
            f"{CHECK_LIMIT:g}); u_{probe}(T) differs by {du:.1e}")
        if progress is not None:
            progress.step()
    return out, refs


def run_peer(w: Scene, methods: list[str] | None = None, tols: list[float] | None = None, repeats: int = 5,
             budget: float = 10.0, log: Callable = print) -> dict:
    """The peer's points for every amplitude, method and tolerance of a work_precision file: a dict ready for
    JSON (see `write_points`). The timed repeats of a point stop after `budget` seconds (at least three); a
    method whose median solve takes longer than `budget` is not run at tighter tolerances (recorded as
    skipped). Its progress (points done, elapsed, time left) goes to stderr every few seconds (`cli.Progress`)."""
    methods = methods or DEFAULT_METHODS
    tols = sorted(tols or DEFAULT_TOLS, reverse=True)
    chain, amps, e_ref, u_ref, probe, window = problem(w)
    # progress on stderr (about 1.5 min for the paper's file): the model check's solves, then every point, each
    # weighted by its solves' expected cost
    weights = [solve_cost("DOP853", CHECK_TOL)] * len(amps) + [
        point_cost(method, tol, repeats, budget) for _ in amps for method in methods for tol in tols]
    progress = cli.Progress("SciPy peer", weights, "solves and points")
    check, refs = check_model(w, log=log, progress=progress)
    points = []
    for ia, a in enumerate(amps):
        for method in methods:
            skip = False
            for tol in tols:
                pt = {"amplitude": float(a), "method": method, "tol": tol}
                if skip:
                    pt.update(status="skipped", reason=f"a looser tolerance took over {budget:g} s")
                    points.append(pt)
                    progress.step()
                    continue
                # untimed run with the window (error in u), then the timed runs without
                s = solve(chain, a, method, tol, probe=probe, window=window)
                if not s.ok:
                    pt.update(status="failed", reason=str(s.message))
                    points.append(pt)
                    progress.step()
                    continue
                med, last, times = timed(chain, a, method, tol, repeats=repeats, budget=budget)
                ref_u = np.interp(s.window_t, refs[ia].window_t, refs[ia].window_u)
                pt.update(status="ok", wall_time=med, wall_time_min=min(times), repeats=len(times),
                          injected=last.injected, error_energy=abs(last.injected - e_ref[ia]) / abs(e_ref[ia]),
                          error_u_final=abs(last.u_final[probe - 1] - u_ref[ia]),
                          error_u=float(np.max(np.abs(s.window_u - ref_u))),
                          nfev=last.nfev, steps=last.steps, mean_dt=chain.t_final / max(last.steps, 1))
                points.append(pt)
                log(f"  A = {a:g} {method:6s} tol {tol:7.0e}: {med * 1e3:9.2f} ms (median of {len(times)}), "
                    f"error {pt['error_energy']:.2e} (energy), {pt['error_u']:.1e} (u), {last.nfev} f-evals, "
                    f"{last.steps} steps")
                progress.step()
                if med > budget:
                    skip = True
    return {"what": "SciPy solve_ivp peer of supratrans (postprocess/peer_scipy.py)",
            "source": w.path, "probe_site": probe, "error_window": window,
            "parameters": {k: w.params[k] for k in MODEL_PARAMETERS},
            "segments": [[t0, t1] for t0, t1, _ in chain.segments()],
            "atol_scale": "tol * (A for u, A*Omega for v, A^2 c^2 for W)",
            "timing": f"median of up to {repeats} solves, time.perf_counter around solve_ivp, t_eval=None",
            "check": check, "points": points,
            "versions": versions()}


def versions() -> dict:
    """Versions of Python, NumPy and SciPy, and the machine, for the record of a peer run."""
    import platform  # noqa: PLC0415

    import scipy  # noqa: PLC0415

    return {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
            "machine": platform.machine(), "processor": platform.processor() or platform.machine()}


def write_points(result: dict, path: Any) -> Path:
    """Write the peer's result as JSON (NaN as null)."""

    def clean(x):
        if isinstance(x, float) and not math.isfinite(x):
            return None
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v) for v in x]
        if isinstance(x, np.generic):
            return clean(x.item())
        return x

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(clean(result), indent=1) + "\n")
    tmp.replace(path)
    return path


def read_points(path: Any) -> dict:
    """The peer's points written by `write_points`; PlotError (one line) when unusable."""
    p = Path(path)
    if not p.is_file():
        raise PlotError(p, "no such file")
    try:
        r = json.loads(p.read_text())
        r["points"]  # noqa: B018
    except (ValueError, KeyError, TypeError) as exc:
        raise PlotError(p, f"not a peer result file ({type(exc).__name__}: {str(exc).splitlines()[0][:80]})") from None
    return r


# ------------------------------------------------------------------------------------------------ command line


def main(argv: list[str] | None = None) -> int:
    """The command line of `peer_scipy.py`; returns the exit status (0 ok, 1 the model check failed, 2 an
    unusable file)."""
    ap = cli.parser("peer_scipy.py", __doc__, argv)
    ap.add_argument("h5", metavar="WORK_PRECISION.h5", help="file of the scene work_precision")
    ap.add_argument("-o", "--output", metavar="JSON", help="where to write the points (default: "
                                                           "<file>_peer.json next to the file)")
    ap.add_argument("--methods", nargs="+", default=DEFAULT_METHODS, choices=["DOP853", "RK45", "RK23"])
    ap.add_argument("--tols", nargs="+", type=float, default=DEFAULT_TOLS, metavar="TOL")
    ap.add_argument("--repeats", type=int, default=5, help="timed solves per point, median (default 5)")
    ap.add_argument("--check", action="store_true", help="only the model check (exit 1 when it fails)")
    args = ap.parse_args(argv)
    try:
        w = read_work_precision(args.h5)
        if args.check:
            check, _ = check_model(w, progress=cli.Progress("SciPy model check", len(problem(w)[1]), "amplitudes"))
            return 0 if all(c["passed"] for c in check) else 1
        result = run_peer(w, methods=args.methods, tols=args.tols, repeats=args.repeats)
        out = Path(args.output) if args.output else output_path(w.path, "_peer.json")
        write_points(result, out)
        print(f"wrote {out}", file=sys.stderr)
        return 0 if all(c["passed"] for c in result["check"]) else 1
    except PlotError as exc:
        print(exc.line(), file=sys.stderr)
        return 2
