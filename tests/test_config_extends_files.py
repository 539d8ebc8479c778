"""`extends` in an untrusted config reads only a regular TOML file of bounded size, never a device or a FIFO."""

from __future__ import annotations

import os
import threading

import pytest

from jointwear.config import load_config
from jointwear.schema import ConfigError


def load_error(path) -> str:
    """The message of loading ``path``, from a thread given 20 s: a read of /dev/zero or a FIFO never ends."""
    out = {}

    def load():
        try:
            load_config(path)
        except ConfigError as exc:
            out["error"] = str(exc)
        except BaseException as exc:  # MemoryError and the like are failures of the test
            out["error"] = f"{type(exc).__name__}: {exc}"

    worker = threading.Thread(target=load, daemon=True)
    worker.start()
    worker.join(20)
    assert not worker.is_alive(), f"loading {path} did not end"
    return out.get("error", "")


def test_extends_reads_only_regular_files(tmp_path):
    (tmp_path / "a.toml").write_text('extends = "/dev/zero"\n', encoding="utf-8")
    assert "a.toml: extends: '/dev/zero' is not a regular file" in load_error(tmp_path / "a.toml")
    os.mkfifo(tmp_path / "fifo.toml")  # opening a FIFO for reading must not wait for a writer
    (tmp_path / "b.toml").write_text('extends = "fifo.toml"\n', encoding="utf-8")
    assert "b.toml: extends: " in (err := load_error(tmp_path / "b.toml")) and "not a regular file" in err, err


def test_extends_reads_at_most_a_megabyte(tmp_path):
    (tmp_path / "big.toml").write_text("#" * 2_000_000 + "\n", encoding="utf-8")
    (tmp_path / "a.toml").write_text('extends = "big.toml"\n', encoding="utf-8")
    with pytest.raises(ConfigError, match="a.toml: extends: file .*big.toml' is larger than 1,000,000 bytes"):
        load_config(tmp_path / "a.toml")


def test_extends_of_a_small_file_still_works(tmp_path):
    (tmp_path / "a.toml").write_text('extends = "jin2025_flapping_wing"\nname = "mine"\n', encoding="utf-8")
    (tmp_path / "b.toml").write_text('extends = "a.toml"\n', encoding="utf-8")
    assert load_config(tmp_path / "b.toml").name == "mine"


def test_a_results_folders_config_json_is_read_only_if_a_regular_file(tmp_path):
    # a received results folder: its config.json is read whole, so it gets the same checks as a TOML config
    folder = tmp_path / "results"
    folder.mkdir()
    (folder / "config.json").symlink_to("/dev/zero")
    assert "is not a regular file" in load_error(folder / "config.json")
