"""A shared library cut short is found before the dynamic loader maps it (walk3d.io.elf):
CasADi's own library, whole (the control) and cut at several lengths, and a file that is not
ELF."""

import os
from pathlib import Path

import casadi as ca
import pytest

from walk3d.io.elf import elf_problem, library_problem

LIBRARY = next(Path(ca.__file__).parent.glob("_casadi*.so"))


def test_a_whole_library_passes():
    assert elf_problem(LIBRARY) is None


@pytest.mark.parametrize("keep", [0.999, 0.5, 0.01, 200, 10])
def test_a_library_cut_short_is_named(tmp_path, keep):
    data = LIBRARY.read_bytes()
    n = int(len(data) * keep) if keep < 1 else int(keep)
    cut = tmp_path / "lib.so"
    cut.write_bytes(data[:n])
    why = elf_problem(cut)
    assert why is not None and ("cut short" in why or "not an ELF" in why), why


def test_a_file_that_is_not_elf_and_one_that_is_missing(tmp_path):
    text = tmp_path / "lib.so"
    text.write_text("not a library")
    assert elf_problem(text) == "not an ELF file"
    assert "cannot be read" in elf_problem(tmp_path / "none.so")


@pytest.mark.parametrize("kind", ["fifo", "regular"])
def test_a_fifo_is_no_library_and_is_not_waited_on(tmp_path, kind):
    """The loader blocked for ever on a FIFO given as a library; it is refused at once, without
    a read. Negative control: a regular copy of the whole library passes."""
    path = tmp_path / "lib.so"
    if kind == "fifo":
        os.mkfifo(path)
    else:
        path.write_bytes(LIBRARY.read_bytes())
    why = elf_problem(path)
    assert (why is None) if kind == "regular" else why == "not a regular file (a FIFO)", why
    assert library_problem(path) == why


def test_a_bare_name_is_left_to_the_library_path():
    """``libhsl.so`` is looked up on the library path by the loader, not in the working folder."""
    assert library_problem("libhsl.so") is None
    assert "cannot be read" in library_problem("./libhsl-missing.so")
