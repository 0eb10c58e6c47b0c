"""Whether a shared library is whole, before the dynamic loader maps it.

A library cut short (a full disk, a killed copy) can take the process down with a bus error
when the loader touches a page past its end: its digest (:mod:`walk3d.solve.compiled`) only
catches damage done after the digest was written. The ELF header names the program headers,
each loadable segment's extent in the file and the section table; all must lie inside the
file (the ELF-64 and ELF-32 layouts of the System V ABI). It must be a regular file too: the
loader waits for ever on a FIFO.
"""

from __future__ import annotations

import os
import struct
from os import PathLike

from walk3d.io.checks import open_input
from walk3d.io.errors import DataFileError

__all__ = ["elf_problem", "library_problem"]

_PT_LOAD = 1


def elf_problem(path: str | PathLike[str]) -> str | None:
    """Why the ELF file ``path`` is not whole (the reason, one line), or None; also when it is
    no regular file (:func:`walk3d.io.checks.open_input`)."""
    try:
        with open_input(path) as f:
            size = os.fstat(f.fileno()).st_size
            head = f.read(64)
            if head[:4] != b"\x7fELF" or len(head) < 52:
                return "not an ELF file"
            wide, order = head[4] == 2, "<" if head[5] == 1 else ">"
            if wide:
                phoff, shoff = struct.unpack_from(order + "QQ", head, 32)
                phsize, phnum, shsize, shnum = struct.unpack_from(order + "HHHH", head, 54)
                entry, fields = order + "IIQQQQQQ", (2, 5)  # p_offset, p_filesz
            else:
                phoff, shoff = struct.unpack_from(order + "II", head, 28)
                phsize, phnum, shsize, shnum = struct.unpack_from(order + "HHHH", head, 42)
                entry, fields = order + "IIIIIIII", (1, 4)
            if phoff + phsize * phnum > size or shoff + shsize * shnum > size:
                return f"cut short: its headers end past its {size} bytes"
            f.seek(phoff)
            table = f.read(phsize * phnum)
    except DataFileError as exc:  # a folder, FIFO...: "not a regular file (a FIFO)"
        return exc.reason.removeprefix("is ")
    except OSError as exc:
        return f"cannot be read ({exc.strerror or exc})"
    n = struct.calcsize(entry)
    for k in range(phnum):
        ph = struct.unpack_from(entry, table, k * phsize)[: max(fields) + 1]
        offset, filesz = ph[fields[0]], ph[fields[1]]
        if ph[0] == _PT_LOAD and offset + filesz > size:
            return f"cut short: a segment ends at byte {offset + filesz}, past its {size} bytes"
    return None if phsize >= n or not phnum else "malformed program headers"


def library_problem(path: str | PathLike[str]) -> str | None:
    """Why the dynamic loader must not be given ``path`` (one line), or None. A name without a
    folder part (``libhsl.so``) is looked up on the library path, as ``dlopen`` does, and
    passes; a path must be a regular file and a whole ELF file (:func:`elf_problem`)."""
    return elf_problem(path) if os.path.dirname(os.fspath(path)) else None
