"""Saving and loading a fuzz program's last world (in the worker): the binary format, through pickle, must read back
and continue as an exact copy of the world. Part of ``test_fuzz.py``."""

from __future__ import annotations

import copy
import pickle

import tumble

from fuzz_snapshot import diff, snapshot


def check_saved(first) -> list[tuple[str, str]]:
    """The program's last world saved in the binary format (through pickle) and loaded continues bit for bit as
    an exact copy of it, over four fast steps or 0.02 s: the same state, or the same error."""
    w = first.ns["w"]
    try:
        data = pickle.dumps(w)
    except ValueError as e:  # force callbacks cannot be saved
        if "loads" in str(e):
            return []
        raise
    try:
        loaded = pickle.loads(data)
    except (ValueError, tumble.SimulationError) as e:
        return [("SavedWorldRefused", f"the world's own file is refused: {e}\n\nReproducer:\n" + first.reproducer())]
    original = copy.deepcopy(w)
    span = 4 * first.fast_dt if w.mode == "fast" else 0.02
    outcomes = []
    for x in (original, loaded):
        try:
            x.step(span)
            outcomes.append(("ok", snapshot(x)))
        except (ValueError, tumble.SimulationError) as e:
            outcomes.append((type(e).__name__, snapshot(x)))
    # a loaded world numbers its handles afresh (slots of removed objects are not kept): rows, not handles, compare
    def rows(snap):
        return [(name, v) for name, v in snap if not name.endswith("handles")]

    changed = diff(rows(outcomes[0][1]), rows(outcomes[1][1]))
    if changed or outcomes[0][0] != outcomes[1][0]:
        return [("SavedWorldDiffers", f"saved and loaded, the world continues otherwise than a copy of it "
                 f"({outcomes[0][0]} against {outcomes[1][0]}):\n  " + "\n  ".join(changed)
                 + "\n\nReproducer:\n" + first.reproducer())]
    return []
