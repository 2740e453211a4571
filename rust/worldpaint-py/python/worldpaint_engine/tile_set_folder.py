"""The folder a tile set is written to, written whole or not at all.

The tiles are written into a fresh hidden folder beside the output folder (``.<name>.partial-<random>``, on the
same file system, so on a cluster in the same shared folder the workers reach), and the finished set (tiles and
manifest) is renamed into place in one step. A failed or interrupted run removes that folder and any parent folders
it had to create, so nothing is left half-written, and an existing tile set is left exactly as it was. An existing
output folder is refused unless ``overwrite`` is given, and even then only a tile set (a folder holding a worldpaint
``manifest.json``) or an empty folder is replaced: never a folder of other files.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile

from . import _engine

MANIFEST = "manifest.json"
FORMAT = "worldpaint tile set"
FORMAT_VERSION = 1


def is_tile_set(folder):
    """Whether ``folder`` holds a worldpaint tile set's manifest."""
    try:
        with open(os.path.join(folder, MANIFEST), encoding="utf-8") as f:
            return json.load(f).get("format") == FORMAT
    except (OSError, ValueError, AttributeError):
        return False


def current_umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


class TileSetFolder:
    """``out``'s staging folder (``path``), made at once so that an output path that cannot be written is refused
    before any work; ``commit()`` moves it into place, leaving the context without it removes it."""

    def __init__(self, out, overwrite=False):
        self.out = os.path.abspath(os.fspath(out))
        self.overwrite = overwrite
        self.path = None
        self.created = []  # parent folders made for the output, removed again if the run fails
        if os.path.islink(self.out):
            raise _engine.InputError(f"--out {out}: it is a symbolic link; give the folder it points to")
        if os.path.lexists(self.out):
            if not os.path.isdir(self.out):
                raise _engine.InputError(f"--out {out}: it is a file, not a folder for a tile set")
            if not overwrite:
                raise _engine.InputError(f"--out {out}: the folder exists; --overwrite replaces it with the new tile "
                                         f"set")
            if os.listdir(self.out) and not is_tile_set(self.out):
                raise _engine.InputError(f"--out {out}: the folder holds files but no tile set ({MANIFEST}); "
                                         f"--overwrite replaces only a tile set or an empty folder")
        parent = os.path.dirname(self.out)
        missing = []
        while not os.path.lexists(parent):
            missing.append(parent)
            parent = os.path.dirname(parent)
        if not os.path.isdir(parent):
            raise _engine.InputError(f"--out {out}: {parent} is a file, not a folder")
        try:
            for folder in reversed(missing):
                os.mkdir(folder)
                self.created.append(folder)
            self.path = tempfile.mkdtemp(prefix=f".{os.path.basename(self.out)}.partial-",
                                         dir=os.path.dirname(self.out))
            os.chmod(self.path, 0o777 & ~current_umask())  # as a folder made by mkdir: the workers may be others
        except OSError as e:
            self.discard()
            raise _engine.InputError(f"--out {out}: cannot create a folder there ({e.strerror or e})") from None

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        self.discard()
        return False

    def commit(self):
        """Moves the finished tile set into place: renamed over nothing, or over the old one (``overwrite``)."""
        old = None
        if os.path.lexists(self.out):
            if not self.overwrite:
                raise _engine.InputError(f"--out {self.out}: the folder appeared while the tiles were made; "
                                         f"--overwrite replaces it")
            old = tempfile.mkdtemp(prefix=f".{os.path.basename(self.out)}.old-", dir=os.path.dirname(self.out))
            os.replace(self.out, old)  # onto the fresh empty folder: the old set stays whole until it is removed
        try:
            os.rename(self.path, self.out)
        except OSError:
            if old is not None:
                os.replace(old, self.out)
            raise
        self.path, self.created = None, []
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)

    def discard(self):
        """Removes what was made for a run that did not finish (a no-op after ``commit``)."""
        if self.path is not None:
            shutil.rmtree(self.path, ignore_errors=True)
            self.path = None
        for folder in reversed(self.created):
            try:
                os.rmdir(folder)
            except OSError:
                break  # something else was put there meanwhile: leave it
        self.created = []
