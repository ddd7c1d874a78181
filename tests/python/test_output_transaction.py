"""Result.write writes its folder as one transaction: all or nothing, one writer at a time."""
import fcntl
import os

import pytest

import hemivem


def test_a_failed_write_keeps_the_previous_set(tmp_path, small_scene):
    out = tmp_path / "out"
    hemivem.solve(small_scene, linear="eigen").write(out, files=["result.json", "contact.csv", "history.csv"])
    (out / "history.csv").unlink()
    (out / "history.csv").mkdir()  # a name of the set taken by a folder: the new set cannot go in
    before = {p.name: p.is_dir() for p in out.iterdir()}
    old_result = (out / "result.json").read_bytes()
    small_scene.set("contact.gap", 0.0123)
    with pytest.raises(hemivem.InputError, match="keeps its previous outputs"):
        hemivem.solve(small_scene, linear="eigen").write(out, files=["result.json", "contact.csv", "history.csv"])
    assert {p.name: p.is_dir() for p in out.iterdir()} == before
    assert (out / "result.json").read_bytes() == old_result
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_a_second_writer_is_refused(tmp_path, small_scene):
    out = tmp_path / "out"
    r = hemivem.solve(small_scene, linear="eigen")
    with open(tmp_path / ".out.hemivem-lock", "w") as lock:  # another process writing the folder
        fcntl.flock(lock, fcntl.LOCK_EX)
        with pytest.raises(hemivem.InputError, match="another hemivem run is writing"):
            r.write(out)
        assert not out.exists()
    assert [p.name for p in r.write(out)][0] == "result.json"
