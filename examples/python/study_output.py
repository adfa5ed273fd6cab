"""What the Python examples share: the base-parameter error they score estimates by, the CSV
table every example writes, and matplotlib when it is installed."""
import csv
import os

import numpy as np


def base_error(beta, truth):
    """RMS over base parameters of |beta_j - truth_j| / s_j, s_j = |truth_j| (the mean true
    magnitude for a true value of 0): dynid's base-parameter error."""
    scale = np.abs(truth)
    nonzero = scale > 1e-9 * scale.mean()
    scale = np.where(nonzero, scale, scale[nonzero].mean() if nonzero.any() else 1.0)
    return float(np.sqrt(np.mean(((beta - truth) / scale) ** 2)))


def write_table(out_dir, name, rows):
    """Writes rows (dicts with the same keys) as out_dir/name; returns the path."""
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, name)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {path}")
    return path


def pyplot():
    """matplotlib.pyplot without a display, or None (and a line saying so) when not installed."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: the table is the result")
        return None
    return plt


def save_figure(fig, out_dir, name):
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    print(f"wrote {path}")
