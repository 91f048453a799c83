"""``simgrasp labels``: draw objects with their labeled handle regions, for a person to check;
``--osd`` draws the handles we labeled in real osd-learn scenes instead, ``--real`` those of the
real clouds of a ``detect-eval --real`` manifest."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from simgrasp.cli.options import YcbSource
from simgrasp.config import setting
from simgrasp.errors import SimgraspError

EXAMPLES = ("simgrasp labels --objects gen_mug,025_mug --out out/labels",)
"""Command lines shown by ``--help``."""


@dataclass(frozen=True, kw_only=True)
class Options(YcbSource):
    objects: tuple[str, ...] = setting(("all",), main=True)
    """Object names and/or the sets generated, families, paper, ycb, all."""
    seed: int = 0
    """Sizes of generated tools named without _s<seed>."""
    out: Path = setting(Path("out/labels"), output="dir", main=True)
    """Output directory (one PNG per object or scene)."""
    osd: tuple[str, ...] = ()
    """Draw the labeled pot handles of these osd-learn scenes instead (learn33,... or all)."""
    real: tuple[str, ...] = ()
    """Draw the labeled handles of these clouds of --manifest instead (names or all)."""
    manifest: Path | None = None
    """With --real: the real-data manifest (default: models/handles/real_detect.toml)."""
    real_dir: str | None = None
    """With --osd or --real: real data root holding osd-learn/ (default: $SIMGRASP_REAL_DIR,
    else ../shared/real)."""

    def _check(self) -> None:
        """Refuse flags the chosen drawing would ignore (given at a value other than their
        default: one at its default cannot be told from one not given)."""
        if not self.objects:
            raise SimgraspError(
                "--objects is empty: give object names or a set (generated, paper, ycb, all)"
            )
        if self.osd and self.real:
            raise SimgraspError("--osd and --real conflict: draw one kind of scene at a time")
        scenes = "--osd" if self.osd else "--real" if self.real else None
        if scenes is not None and self.objects != ("all",):
            raise SimgraspError(f"--objects and {scenes} conflict: {scenes} draws scenes")
        if scenes is not None and self.seed != 0:
            raise SimgraspError(f"--seed and {scenes} conflict: --seed sizes generated tools")
        if self.manifest is not None and not self.real:
            raise SimgraspError("--manifest needs --real (the names of its clouds to draw)")
        if self.real_dir is not None and scenes is None:
            raise SimgraspError("--real-dir needs --osd or --real (it holds their clouds)")


def run(options: Options) -> int:
    if options.osd:
        return _run_osd(options)
    if options.real:
        return _run_real(options)
    import numpy as np

    from simgrasp.assets.mesh_object import file_stem
    from simgrasp.assets.object_sets import expand_objects
    from simgrasp.assets.registry import load_object
    from simgrasp.plots.object_labels import draw_label

    options.out.mkdir(parents=True, exist_ok=True)
    for name in expand_objects(options.objects):
        asset = load_object(name, ycb_dir=options.ycb_dir, seed=options.seed)
        path = draw_label(asset, options.out / f"{file_stem(asset.name)}.png")
        share = np.round(asset.handle.contains(asset.mesh.vertices).mean(), 2)
        print(f"{asset.name}: {path} (handle share of mesh vertices {share})")
    return 0


def _run_osd(options: Options) -> int:
    """Draw the labeled handles of the chosen osd-learn scenes."""
    from simgrasp.assets.real import osd_scene_file, read_labeled_scene
    from simgrasp.assets.scene_labels import load_scene_labels
    from simgrasp.plots.scene_labels import draw_scene_label

    labels = load_scene_labels()
    names = tuple(labels) if options.osd == ("all",) else options.osd
    unknown = [n for n in names if n not in labels]
    if unknown:
        raise SimgraspError(f"no handle label for osd scene(s) {', '.join(unknown)}")
    options.out.mkdir(parents=True, exist_ok=True)
    for name in names:
        scene = read_labeled_scene(osd_scene_file(name, options.real_dir))
        path = draw_scene_label(scene, labels[name], options.out / f"{name}.png")
        print(f"{name}: {path} ({len(labels[name].label.regions)} handle region(s))")
    return 0


def _run_real(options: Options) -> int:
    """Draw the labeled handles of the chosen manifest clouds, each cut as detection gets it."""
    from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest
    from simgrasp.plots.real_labels import draw_real_label

    real_dir = Path(options.real_dir) if options.real_dir else None
    clouds = {c.name: c for c in read_manifest(options.manifest, real_dir)}
    names = tuple(clouds) if options.real == ("all",) else options.real
    unknown = [n for n in names if n not in clouds]
    if unknown:
        raise SimgraspError(f"no cloud {', '.join(unknown)} in the manifest")
    options.out.mkdir(parents=True, exist_ok=True)
    for name in names:
        cloud = clouds[name]
        title = f"{name} ({cloud.dataset}, {cloud.split})"
        path, inside = draw_real_label(
            load_real_cloud(cloud), cloud.label, title, options.out / f"{name}.png"
        )
        print(f"{name}: {path} ({len(cloud.label.regions)} region(s), {inside} points)")
    return 0
