"""Read a surftrack event-list file (docs/event_format.md) with numpy and print a summary.

Usage: python3 read_events.py FILE.events [--json]
"""
import json
import sys
import zlib

import numpy as np

KINDS = ["split_edge", "split_face", "collapse", "patch_created", "patch_deleted", "merge"]


def read_events(path):
    b = open(path, "rb").read()
    if b[:8] != b"SURFEVT\0":
        raise ValueError(f"{path}: not an event-list file")
    if zlib.crc32(b[:-4]) != int.from_bytes(b[-4:], "little"):
        raise ValueError(f"{path}: checksum mismatch")
    version, n_ev, n_id, n_as, n_te, _ = (int(x) for x in np.frombuffer(b, "<u4", 6, 8))
    if version != 1:
        raise ValueError(f"{path}: unsupported version {version}")
    o = 32
    ev = np.frombuffer(b, "<u4", n_ev * 9, o).reshape(-1, 9)
    o += 36 * n_ev
    ids = np.frombuffer(b, "<u8", n_id, o)
    o += 8 * n_id
    assigns = np.frombuffer(b, [("target", "<u8"), ("start", "<u4"), ("count", "<u4")], n_as, o)
    o += 16 * n_as
    terms = np.frombuffer(b, [("source", "<u8"), ("weight", "<f4"), ("pad", "<u4")], n_te, o)

    def rule(start, count):
        out = []
        for a in assigns[start:start + count]:
            t = terms[a["start"]:a["start"] + a["count"]]
            out.append({"target": int(a["target"]),
                        "terms": [[int(s), float(w)] for s, w in zip(t["source"], t["weight"])]})
        return out

    events = []
    for k, i0, i1, o0, o1, f0, f1, g0, g1 in ev:
        events.append({"kind": KINDS[k],
                       "inputs": [int(x) for x in ids[i0:i0 + i1]],
                       "outputs": [int(x) for x in ids[o0:o0 + o1]],
                       "forward": rule(f0, f1),
                       "backward": rule(g0, g1)})
    return events


if __name__ == "__main__":
    events = read_events(sys.argv[1])
    if "--json" in sys.argv:
        print(json.dumps(events))
    else:
        counts = {k: sum(e["kind"] == k for e in events) for k in KINDS}
        print(f"{len(events)} events: " + ", ".join(f"{v} {k}" for k, v in counts.items() if v))
