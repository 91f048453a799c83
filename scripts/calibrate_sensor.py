"""Calibrate a depth sensor model against real labeled scans (osd-learn) and show it.

For each 20 cm depth bin from 0.6 to 1.6 m: the real table's local plane-fit residual (5 cm
patches) next to the simulated one, and the share of invalid pixels in a 3-pixel band around
object silhouettes, real vs simulated (see simgrasp.perception.sensors.calibration). Writes
calibration.md (the table against the 25 % goal), calibration.csv and calibration.png.

    python scripts/calibrate_sensor.py --sensor kinect --out docs/results/sensor-calibration
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
import time
from pathlib import Path

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.config.fields import setting
from simgrasp.perception.sensors import SENSORS, KinectConfig, SensorConfig, sensor_config
from simgrasp.perception.sensors.calibration import CalibrationRow, calibration_rows

GOAL = 0.25
"""Largest relative difference of a simulated figure from the real one."""
LITERATURE = {
    "kinect": KinectConfig(
        axial_a=0.0012, axial_b=0.0019, registration_offset=0.0, min_shadow_px=0.0
    )
}
"""Published values before the fit, measured alongside: Nguyen et al.'s axial noise and the
projector's shadow seen from the IR camera, every shadow kept."""


NOTE = (
    "Real: the scans as captured. Simulated: the sensor model applied to each scan's own "
    "geometry, the analytic depth image of its table's fitted plane (what a renderer draws "
    "for a flat table, from the same camera, distances and angles) with the objects' measured "
    "surfaces (holes filled, smoothed) over it. Residual: median over the 5 x 5 cm table "
    "patches of a bin (by mean depth) of the RMS distance to the patch's own plane. Invalid "
    "share: pixels without a return in a band 3 px either side of the object silhouettes (by "
    "the depth of the nearest object pixel); n/a: under 1000 band pixels (osd-learn's objects "
    "stand 0.6 - 1.0 m from the sensor)."
)


def default_real_dir() -> Path:
    """``$SIMGRASP_REAL_DIR``, else ``../shared/real`` beside the repository."""
    env = os.environ.get("SIMGRASP_REAL_DIR")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "shared" / "real"


def scan_paths(real_dir: Path) -> list[Path]:
    """The osd-learn scans under ``real_dir``, in scene order."""
    paths = sorted((real_dir / "osd-learn").glob("learn*.pcd"), key=lambda p: int(p.stem[5:]))
    if not paths:
        raise FileNotFoundError(f"no osd-learn scans under {real_dir} (set SIMGRASP_REAL_DIR)")
    return paths


def _error(value: float) -> str:
    return "n/a" if math.isnan(value) else f"{value:+.0%}"


def _verdict(error: float) -> str:
    return "n/a" if math.isnan(error) else "yes" if abs(error) <= GOAL else "no"


def write_table(
    rows: list[CalibrationRow],
    config: SensorConfig,
    reference: list[CalibrationRow] | None,
    out: Path,
    note: str,
) -> None:
    """calibration.md (the table against the goal) and calibration.csv (every figure)."""
    lines = [f"# Sensor calibration: `{config.name}` against osd-learn", "", note, ""]
    lines += [
        "| depth (m) | patches | residual real (mm) | sim (mm) | diff | within 25 % | band px "
        "| invalid real | sim | diff | within 25 % |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r.low:.1f} - {r.high:.1f} | {r.patches} | {1000 * r.real_residual:.2f} "
        f"| {1000 * r.sim_residual:.2f} | {_error(r.residual_error)} "
        f"| {_verdict(r.residual_error)} | {r.band_pixels} | {r.real_invalid:.3f} "
        f"| {r.sim_invalid:.3f} | {_error(r.invalid_error)} | {_verdict(r.invalid_error)} |"
        for r in rows
    ]
    if reference is not None:
        lines += ["", "The published values before the fit (`LITERATURE` in the script):", ""]
        lines += ["| depth (m) | residual sim (mm) | diff | invalid sim | diff |"]
        lines += ["|---|---|---|---|---|"]
        lines += [
            f"| {r.low:.1f} - {r.high:.1f} | {1000 * r.sim_residual:.2f} "
            f"| {_error(r.residual_error)} | {r.sim_invalid:.3f} | {_error(r.invalid_error)} |"
            for r in reference
        ]
    fields = ", ".join(f"{f.name}={getattr(config, f.name)!r}" for f in dataclasses.fields(config))
    lines += ["", f"Fitted config: `{type(config).__name__}({fields})`", ""]
    (out / "calibration.md").write_text("\n".join(lines))
    with (out / "calibration.csv").open("w", newline="") as stream:
        writer = csv.writer(stream)
        names = [f.name for f in dataclasses.fields(CalibrationRow)]
        writer.writerow(["config"] + names + ["residual_error", "invalid_error"])
        for label, table in (("fitted", rows), ("literature", reference or [])):
            for r in table:
                values = [getattr(r, n) for n in names]
                writer.writerow([label] + values + [r.residual_error, r.invalid_error])


def plot(rows: list[CalibrationRow], name: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    centers = np.array([(r.low + r.high) / 2 for r in rows])
    panels = [
        ("table residual, 5 cm patches (mm)", "real_residual", "sim_residual", 1000.0),
        ("invalid share, 3 px silhouette band", "real_invalid", "sim_invalid", 1.0),
    ]
    figure, axes = plt.subplots(1, 2, figsize=(11, 4))
    for axis, (title, real, sim, scale) in zip(axes, panels, strict=True):
        real_values = scale * np.array([getattr(r, real) for r in rows])
        sim_values = scale * np.array([getattr(r, sim) for r in rows])
        axis.fill_between(
            centers, (1 - GOAL) * real_values, (1 + GOAL) * real_values, alpha=0.2, label="±25 %"
        )
        axis.plot(centers, real_values, "o-", label="real (osd-learn)")
        axis.plot(centers, sim_values, "s--", label=f"simulated ({name})")
        axis.set(title=title, xlabel="depth (m)", xlim=(rows[0].low, rows[-1].high))
        axis.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=100)


@dataclasses.dataclass(frozen=True, kw_only=True)
class Options(Checked):
    sensor: str = setting("kinect", choices=tuple(sorted(SENSORS)))
    """Sensor model calibrated (its defaults)."""
    seed: int = 0
    """Seed of the simulated sensor noise."""
    real_dir: Path = default_real_dir()
    """Real data root holding osd-learn (default: $SIMGRASP_REAL_DIR, else ../shared/real)."""
    out: Path = Path("docs/results/sensor-calibration")
    """Folder of calibration.md, calibration.csv and calibration.png."""


def run(options: Options) -> str:
    """Real and simulated figures per depth bin, written; the table."""
    paths = scan_paths(options.real_dir)
    config = sensor_config(options.sensor)
    reference = LITERATURE.get(options.sensor)
    configs = [config] if reference is None else [config, reference]
    start = time.perf_counter()
    rows, *others = calibration_rows(paths, configs, options.seed)
    seconds = time.perf_counter() - start
    options.out.mkdir(parents=True, exist_ok=True)
    note = f"{len(paths)} scans, seed {options.seed}, {seconds:.0f} s. {NOTE}"
    write_table(rows, config, others[0] if others else None, options.out, note)
    plot(rows, options.sensor, options.out / "calibration.png")
    return (options.out / "calibration.md").read_text()


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())
