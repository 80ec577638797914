"""How to install an optional extra, as the README says it: tumble is installed from its clone, so the command
names the clone's ``python`` folder (run from the clone's root), not a package index."""

from __future__ import annotations

# The README's command for an extra; every message and docstring that tells how to install one says this.
INSTALL_EXTRA = 'pip install "./python[{extra}]"'


def install_hint(extra: str) -> str:
    """The command that installs the optional ``extra`` ("viewer", "usd", "dask", "ray", "test")."""
    return INSTALL_EXTRA.format(extra=extra)
