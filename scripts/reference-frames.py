#!/usr/bin/env python3
"""Recovers the real Animal-AI v1 camera frames that the authors' public repository
(IsmaelTito/SEC) stores, as 84x84 PNGs with their provenance: tests/reference-frames/.

The frames survive only as matplotlib's drawing of them in the notebooks' stored outputs
(`plt.imshow(data[i])` in a 6 x 4 inch figure at 72 dpi, cropped to the axes' bounding box): about
2.6 display pixels per frame pixel, resampled with matplotlib's default "antialiased"
interpolation, which for an enlargement of less than 3x is a Hanning filter of radius one frame
pixel. That drawing is linear in the frame: display = Ay . frame . Ax^T per channel, each display
pixel a normalised Hanning-weighted mix of the (at most two per axis) frame pixels within one
pixel of where its centre falls. The script finds the axes' image edges (the dark spines, refined
by the least-squares residual), solves that system by least squares and rounds. It reports the
residual, and `--validate` measures the whole recovery on frames whose pixels are known: it draws
them with the installed matplotlib exactly so and recovers them.

Only pixels are carried over; no code of the notebooks is run or copied.

    python3 scripts/reference-frames.py MIRROR_DIR COMMIT [--out tests/reference-frames] [--validate]

MIRROR_DIR holds the notebooks as they are at COMMIT (for example a checkout of that commit).
Needs numpy and Pillow; --validate also matplotlib.
"""

import argparse
import base64
import io
import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

REPOSITORY = "IsmaelTito/SEC"
SIDE = 84

# (notebook, cell index, output index, data set the notebook loads, image index in it, name).
# The random-projection notebook draws permanence image 58 three times (cells 5, 10, 18): the
# three drawings are recovered separately and must agree.
SOURCES = [
    ("notebooks/train_autoencoder_animalai.ipynb", 10, 0, "detour", 20, "detour-20"),
    ("notebooks/train_autoencoder_classic.ipynb", 10, 0, "permanence", 25, "permanence-25"),
    ("notebooks/train_random_projections_gaussian.ipynb", 5, 0, "permanence", 58, "permanence-58"),
    ("notebooks/train_random_projections_gaussian.ipynb", 10, 0, "permanence", 58, "permanence-58"),
    ("notebooks/train_random_projections_gaussian.ipynb", 18, 0, "permanence", 58, "permanence-58"),
]


# The overview figures' views, cut out at the figures' own resolution (left, top, right, bottom):
# screenshots of the Unity window, no 84 x 84 observation (README.md there).
FIGURE_CROPS = [
    ("figures/fig2_sec_detail.png", (23, 98, 174, 190), "fig2-storage-1-t-3"),
    ("figures/fig2_sec_detail.png", (194, 98, 345, 191), "fig2-storage-1-t-2"),
    ("figures/fig2_sec_detail.png", (368, 98, 520, 191), "fig2-storage-1-t-1"),
    ("figures/fig2_sec_detail.png", (539, 98, 691, 191), "fig2-storage-1-t"),
    ("figures/fig2_sec_detail.png", (893, 98, 1043, 191), "fig2-storage-2-t-3"),
    ("figures/fig2_sec_detail.png", (1067, 98, 1218, 191), "fig2-storage-2-t-2"),
    ("figures/fig2_sec_detail.png", (1238, 98, 1389, 191), "fig2-storage-2-t-1"),
    ("figures/fig2_sec_detail.png", (1409, 98, 1560, 191), "fig2-storage-2-t"),
    ("figures/fig2_sec_detail.png", (80, 943, 241, 1039), "fig2-retrieval-s-t"),
    ("figures/fig1_sec.png", (190, 313, 316, 439), "fig1-input"),
]


def hanning_matrix(n_display, lo, hi):
    """Rows: display pixels; columns: frame pixels. The frame spans display coordinates
    [lo, hi]; a display pixel's centre is at d + 0.5."""
    scale = SIDE / (hi - lo)
    u = (np.arange(n_display)[:, None] + 0.5 - lo) * scale
    x = np.abs(u - (np.arange(SIDE)[None, :] + 0.5))
    a = np.where(x < 1.0, 0.5 + 0.5 * np.cos(np.pi * np.minimum(x, 1.0)), 0.0)
    s = a.sum(axis=1, keepdims=True)
    return np.divide(a, s, out=np.zeros_like(a), where=s > 0)


def spines(img):
    """The dark axes lines: (top, bottom) rows and (left, right) columns."""
    dark = img.sum(axis=2) < 200
    rows = np.where(dark.sum(axis=1) > 0.6 * img.shape[1])[0]
    cols = np.where(dark.sum(axis=0) > 0.6 * img.shape[0])[0]
    return (rows.min(), rows.max()), (cols.min(), cols.max())


def solve_axis(display, inner, lo_guess, hi_guess, axis):
    """Least-squares frame for one axis over a small search of the image edges; returns the
    edges, the matrix and the RMS residual."""
    best = None
    for dlo in np.linspace(-1.0, 1.0, 21):
        for dhi in np.linspace(-1.0, 1.0, 21):
            lo, hi = lo_guess + dlo, hi_guess + dhi
            a = hanning_matrix(display.shape[axis], lo, hi)[inner]
            d = np.take(display, inner, axis=axis)
            d2 = np.moveaxis(d, axis, 0).reshape(len(inner), -1)
            x, *_ = np.linalg.lstsq(a, d2, rcond=None)
            res = np.sqrt(np.mean((a @ x - d2) ** 2))
            if best is None or res < best[3]:
                best = (lo, hi, a, res)
    return best


def recover(fig):
    """84x84x3 uint8 frame from a drawn figure (H x W x 3 uint8); and a record of the fit."""
    img = fig.astype(np.float64)
    (top, bottom), (left, right) = spines(fig)
    # The image lies between the spines; the pixels the spines touch are left out of the fit.
    rows = np.arange(top + 2, bottom - 1)
    cols = np.arange(left + 2, right - 1)
    block = img[np.ix_(rows, cols)]
    lo_r, hi_r, ay, res_r = solve_axis(img[:, cols], rows, top + 0.5, bottom + 0.5, 0)
    lo_c, hi_c, ax, res_c = solve_axis(img[rows, :], cols, left + 0.5, right + 0.5, 1)
    frame = np.zeros((SIDE, SIDE, 3))
    ay_p, ax_p = np.linalg.pinv(ay), np.linalg.pinv(ax)
    for ch in range(3):
        frame[:, :, ch] = ay_p @ block[:, :, ch] @ ax_p.T
    out = np.clip(np.rint(frame), 0, 255).astype(np.uint8)
    redraw = np.stack([ay @ out[:, :, ch].astype(np.float64) @ ax.T for ch in range(3)], axis=2)
    residual = np.abs(redraw - block)
    return out, {
        "spines": {"rows": [int(top), int(bottom)], "cols": [int(left), int(right)]},
        "image_edges": {"rows": [round(lo_r, 2), round(hi_r, 2)], "cols": [round(lo_c, 2), round(hi_c, 2)]},
        "redraw_mean_abs_error": round(float(residual.mean()), 3),
        "redraw_max_abs_error": round(float(residual.max()), 3),
    }


def notebook_png(path, cell, output):
    nb = json.loads(Path(path).read_text())
    data = nb["cells"][cell]["outputs"][output]["data"]["image/png"]
    raw = base64.b64decode(data if isinstance(data, str) else "".join(data))
    return np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"))


def draw_like_the_notebooks(frame):
    """The notebooks' drawing of a known frame with the installed matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(6, 4), dpi=72)
    plt.imshow(frame)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=72, bbox_inches="tight")
    plt.close(fig)
    return np.asarray(Image.open(buf).convert("RGB")), matplotlib.__version__


def validate(frames):
    """Draws each known frame as the notebooks did and recovers it: how exact is the recovery?"""
    rows = []
    for name, truth in frames:
        drawn, version = draw_like_the_notebooks(truth)
        got, fit = recover(drawn)
        err = np.abs(got.astype(int) - truth.astype(int))
        rows.append(
            {
                "frame": name,
                "matplotlib": version,
                "drawn_size": list(drawn.shape[:2]),
                "exact_share": round(float((err == 0).mean()), 4),
                "within_1_share": round(float((err <= 1).mean()), 4),
                "mean_abs_error": round(float(err.mean()), 4),
                "max_abs_error": int(err.max()),
                "redraw_mean_abs_error": fit["redraw_mean_abs_error"],
            }
        )
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("mirror", type=Path)
    p.add_argument("commit")
    p.add_argument("--out", type=Path, default=Path("tests/reference-frames"))
    p.add_argument("--validate", nargs="*", type=Path, metavar="PNG", help="84x84 frames with known pixels")
    a = p.parse_args()
    if len(a.commit) != 40:
        sys.exit("commit: give the full 40-digit hash")
    a.out.mkdir(parents=True, exist_ok=True)
    records, recovered = [], {}
    for nb, cell, output, dataset, index, name in SOURCES:
        fig = notebook_png(a.mirror / nb, cell, output)
        frame, fit = recover(fig)
        recovered.setdefault(name, []).append(frame)
        records.append(
            {
                "frame": name,
                "repository": REPOSITORY,
                "commit": a.commit,
                "notebook": nb,
                "cell": cell,
                "output": output,
                "dataset": dataset,
                "image_index": index,
                "figure_size": list(fig.shape[:2]),
                **fit,
            }
        )
    agreement = {}
    for name, frames in recovered.items():
        Image.fromarray(frames[0]).save(a.out / f"{name}.png", optimize=False)
        if len(frames) > 1:
            diffs = [int(np.abs(f.astype(int) - frames[0].astype(int)).max()) for f in frames[1:]]
            agreement[name] = {"drawings": len(frames), "max_abs_difference": max(diffs)}
    out = {
        "about": "Real Animal-AI v1 observations recovered from matplotlib drawings in the authors' "
        "notebooks (scripts/reference-frames.py); each PNG is the first listed drawing of it.",
        "sources": records,
        "agreement_between_drawings": agreement,
    }
    (a.out / "figures").mkdir(exist_ok=True)
    for figure, box, name in FIGURE_CROPS:
        Image.open(a.mirror / figure).convert("RGB").crop(box).save(a.out / "figures" / f"{name}.png")
    if a.validate:
        truths = [(str(v.name), np.asarray(Image.open(v).convert("RGB"))) for v in a.validate]
        out["validation"] = validate(truths)
    (a.out / "provenance.json").write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
