"""The output of the simulations: values rounded to 6 decimals (`rnd`), the JSON file (`dump_json`: header
keys sorted, one row per line), the flat CSV (`csv_text`), atomic writes (`write_tables`: both files of a
table). Used by closing.py, power_closing.py and the replays."""
import csv
import io
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np


def rnd(x):
    if isinstance(x, dict):
        return {k: rnd(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [rnd(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = round(float(x), 6)
        return 0.0 if v == 0 else v
    return x


def flatten(x, pre=""):
    out = {}
    if isinstance(x, dict):
        for k, v in x.items():
            out.update(flatten(v, f"{pre}{k}."))
    elif isinstance(x, list) and len(x) == 3 and all(isinstance(v, float) for v in x):
        for a, v in zip("xyz", x):
            out[f"{pre}{a}"] = v
    elif isinstance(x, list):
        out[pre[:-1]] = "+".join(str(v) for v in x)
    else:
        out[pre[:-1]] = x
    return out


def write_atomic(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    with os.fdopen(fd, "w", newline="") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def dump_json(header, rows):
    parts = ["{"]
    items = sorted(header.items())
    for k, v in items:
        parts.append(f"{json.dumps(k)}: {json.dumps(rnd(v), sort_keys=True)},")
    parts.append('"rows": [')
    parts.append(",\n".join(json.dumps(rnd(r), sort_keys=True) for r in rows))
    parts.append("]}")
    return "\n".join(parts) + "\n"


def csv_text(rows):
    flat = [flatten(rnd(r)) for r in rows]
    cols = sorted({k for f in flat for k in f})
    buf = io.StringIO()
    wr = csv.writer(buf, lineterminator="\n")
    wr.writerow(cols)
    for f in flat:
        line = []
        for c in cols:
            v = f.get(c)
            if v is None:
                line.append("")
            elif isinstance(v, bool):
                line.append("true" if v else "false")
            elif isinstance(v, float):
                line.append(f"{v:.6f}")
            else:
                line.append(str(v))
        wr.writerow(line)
    return buf.getvalue()


def write_tables(out_dir, stem, header, rows, t_start):
    """`stem`.json (header + rows) and `stem`.csv (the rows) in `out_dir`, atomically; says so."""
    out = Path(out_dir)
    write_atomic(out / f"{stem}.json", dump_json(header, rows))
    write_atomic(out / f"{stem}.csv", csv_text(rows))
    print(f"wrote {out / stem}.json and .csv: {len(rows)} rows in {time.time() - t_start:.1f} s")
