"""Persistent evaluation store: every model call of a study, in one SQLite file.

The store is what makes a study resumable. Each completed model call (success or failure) is one row of
the ``calls`` table, committed as soon as the call completes, so a study killed at any moment (Ctrl-C,
``kill -9``, power loss: the database runs in WAL mode with ``synchronous=FULL``) loses at most the calls
that were still running. A resumed study looks every input row up by its exact bytes and is served the
stored outcome instead of calling the model again.

Layout of the file (``<out>/evaluations.sqlite``):

``meta``      key/value pairs: ``config_hash``, ``code_version``, ``format``, ``created_at``.
``sessions``  one row per open (fresh, resumed), with the code version of that session.
``calls``     one row per completed model call: ``tag`` (which model, when a study has several), ``key``
              (SHA-256 of the input row's float64 bytes and its length), ``x`` (the input row, exact
              little-endian float64 bytes), ``status`` (``ok``/``failed``/``timeout``), ``reason``,
              ``out_kind``/``out_names``/``y`` (the outputs, exact float64 bytes; NULL for a failure),
              ``wall_s``, ``started_at``/``finished_at`` (UTC ISO 8601), ``worker``.

Only the process that owns the study writes to the store (workers return their results to it), so there
is a single writer.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import functools
import hashlib
import json
import os
import sqlite3
import subprocess
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np

__all__ = [
    "CallRecord",
    "ConfigChangedError",
    "EvaluationStore",
    "StoreError",
    "StoreExistsError",
    "StoreStats",
    "code_version",
    "config_hash",
    "read_only_uri",
    "row_key",
]

STORE_FILENAME = "evaluations.sqlite"
FORMAT_VERSION = "1"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS sessions (
    id           INTEGER PRIMARY KEY AUTOINCREMENT,
    opened_at    TEXT NOT NULL,
    mode         TEXT NOT NULL,
    code_version TEXT NOT NULL,
    pid          INTEGER NOT NULL
);
CREATE TABLE IF NOT EXISTS calls (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    tag         TEXT NOT NULL,
    key         TEXT NOT NULL,
    d           INTEGER NOT NULL,
    x           BLOB NOT NULL,
    status      TEXT NOT NULL,
    reason      TEXT,
    out_kind    TEXT,
    out_names   TEXT,
    y           BLOB,
    wall_s      REAL,
    started_at  TEXT,
    finished_at TEXT,
    worker      TEXT
);
CREATE INDEX IF NOT EXISTS calls_tag_key ON calls (tag, key);
"""


class StoreError(RuntimeError):
    """Base class of the evaluation store's errors."""


class StoreExistsError(StoreError):
    """A store already exists where a fresh study was asked for."""


class ConfigChangedError(StoreError):
    """A study was resumed with a configuration different from the interrupted one."""


def _exists_error(db: Path) -> StoreExistsError:
    return StoreExistsError(f"an evaluation store already exists in {db.parent} from an earlier run; "
                            "resume it (--resume; resume=True in Python), overwrite it (--overwrite; overwrite=True), "
                            "or use a new --out folder")


def _meta_error(db: Path, meta: dict, config_hash: str) -> StoreError | None:
    """Why a store with this ``meta`` cannot be resumed with ``config_hash`` (None: it can)."""
    if meta["config_hash"] != config_hash:
        return ConfigChangedError(
            f"the config changed since the interrupted run: the store in {db.parent} was "
            f"written with config hash {meta['config_hash'][:12]}..., this run has "
            f"{config_hash[:12]}...; use a new --out folder (or the original config)")
    if meta.get("format") != FORMAT_VERSION:
        return StoreError(f"the evaluation store in {db.parent} has format {meta.get('format')!r}, "
                          f"this version reads format {FORMAT_VERSION!r}; use a new --out folder")
    return None


# ----------------------------------------------------------------------------------------------------
# hashing helpers


def _canonical(obj: Any) -> Any:
    """A JSON-able, order-independent version of ``obj`` for hashing."""
    if isinstance(obj, Mapping):
        return {str(k): _canonical(v) for k, v in sorted(obj.items(), key=lambda kv: str(kv[0]))}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return {"__ndarray__": obj.dtype.str, "shape": list(obj.shape), "data": obj.tolist()}
    if isinstance(obj, (np.floating, float)):
        return {"__float__": float(obj).hex()}  # exact, and NaN/inf-safe
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, Path):
        return str(obj)
    if hasattr(obj, "model_dump"):  # pydantic models
        return _canonical(obj.model_dump())
    if hasattr(obj, "__dataclass_fields__"):
        from dataclasses import asdict

        return _canonical(asdict(obj))
    return obj


def config_hash(config: Any) -> str:
    """SHA-256 (hex) of a configuration: dicts (key order ignored), lists, numbers, strings, numpy
    arrays, dataclasses and pydantic models. Floats are hashed exactly (``float.hex``)."""
    text = json.dumps(_canonical(config), sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def row_bytes(x: np.ndarray) -> bytes:
    return np.ascontiguousarray(x, dtype="<f8").tobytes()


def row_key(x: np.ndarray) -> str:
    """The store key of one input row: SHA-256 of its exact little-endian float64 bytes and length."""
    b = row_bytes(np.asarray(x, dtype=np.float64).ravel())
    return hashlib.sha256(len(b).to_bytes(8, "little") + b).hexdigest()


def code_version(with_git: bool = True) -> str:
    """``jointwear.__version__``, plus ``git describe --always --dirty`` of the source tree when the
    package runs from a git checkout (``"0.1.0+g1a2b3c4-dirty"``)."""
    try:
        from jointwear import __version__ as version
    except Exception:  # pragma: no cover - compute used outside the package
        version = "unknown"
    if not with_git:
        return version
    checkout = Path(__file__).resolve().parents[3]  # <checkout>/src/jointwear/compute
    if not (checkout / ".git").exists():  # an installed package: a surrounding repository is not its source
        return version
    commit = source_commit(checkout)
    return version if commit is None else f"{version}+g{commit}"


@functools.cache
def source_commit(checkout: Path) -> str | None:
    """``git describe --always --dirty`` of ``checkout``, read once per process: the commit of the code this process
    loaded (a checkout that moves later does not change what it runs), so a Dask worker started before a ``git pull``
    is told from the client that ran it."""
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=checkout, capture_output=True,
                             text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else None


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="microseconds")


# ----------------------------------------------------------------------------------------------------
# records


@dataclass(frozen=True)
class CallRecord:
    """The outcome of one model call, as stored.

    ``outputs`` is a float64 array, a dict of float64 arrays (``out_kind == "dict"``) or ``None`` for a
    failed call. ``status`` is ``"ok"``, ``"failed"`` or ``"timeout"``.
    """

    x: np.ndarray
    status: str
    reason: str | None
    outputs: np.ndarray | dict[str, np.ndarray] | None
    wall_s: float
    started_at: str | None = None
    finished_at: str | None = None
    worker: str | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def _encode_outputs(outputs) -> tuple[str | None, str | None, bytes | None]:
    if outputs is None:
        return None, None, None
    if isinstance(outputs, Mapping):
        names, chunks = [], []
        for k, v in outputs.items():
            a = np.asarray(v, dtype=np.float64)
            names.append([str(k), list(a.shape)])
            chunks.append(row_bytes(a.ravel()))
        return "dict", json.dumps(names), b"".join(chunks)
    a = np.asarray(outputs, dtype=np.float64)
    return "array", json.dumps(list(a.shape)), row_bytes(a.ravel())


def _decode_outputs(kind, names, blob):
    if kind is None or blob is None:
        return None
    flat = np.frombuffer(blob, dtype="<f8").astype(np.float64)
    if kind == "array":
        return flat.reshape(json.loads(names))
    out, i = {}, 0
    for name, shape in json.loads(names):
        n = int(np.prod(shape, dtype=np.int64))
        out[name] = flat[i : i + n].reshape(shape).copy()
        i += n
    return out


@dataclass(frozen=True)
class StoreStats:
    """Counts over the ``calls`` table. ``n_repeated`` counts rows whose (tag, input) was already
    stored: it is 0 unless a call was evaluated twice."""

    n_calls: int
    n_ok: int
    n_failed: int
    n_timeout: int
    n_repeated: int
    total_wall_s: float
    n_sessions: int

    def as_dict(self) -> dict:
        return dict(self.__dict__)


# ----------------------------------------------------------------------------------------------------
# the store


class EvaluationStore:
    """SQLite store of model calls. Create with :meth:`open`; use as a context manager or call
    :meth:`close`."""

    def __init__(self, db_path: Path, conn: sqlite3.Connection, config_hash: str, code_version: str):
        self.path = Path(db_path)
        self._conn = conn
        self.config_hash = config_hash
        self.code_version = code_version

    # -- opening ------------------------------------------------------------------------------------
    @staticmethod
    def db_path(path: str | os.PathLike) -> Path:
        """The database file for ``path``: ``path`` itself when it ends in ``.sqlite``/``.db``,
        otherwise ``path/evaluations.sqlite`` (``path`` is an output folder)."""
        p = Path(path)
        if p.suffix in (".sqlite", ".sqlite3", ".db"):
            return p
        return p / STORE_FILENAME

    @classmethod
    def exists(cls, path: str | os.PathLike) -> bool:
        return cls.db_path(path).exists()

    @classmethod
    def refusal(cls, path: str | os.PathLike, config_hash: str, *, resume: bool = False,
                overwrite: bool = False) -> StoreError | None:
        """The error :meth:`open` would raise with these arguments, found read-only (nothing is created, changed
        or recorded), so that a study can refuse before it writes anything; None when it would open."""
        db = cls.db_path(path)
        if not db.exists():
            return None
        if not resume:
            return None if overwrite else _exists_error(db)
        try:
            with contextlib.closing(sqlite3.connect(read_only_uri(db), uri=True, timeout=5)) as con:
                meta = dict(con.execute("SELECT key, value FROM meta").fetchall())
        except sqlite3.Error as exc:
            return _damaged_error(db, exc)  # else not readable as a store yet (killed before its first commit)
        return _meta_error(db, meta, config_hash) if "config_hash" in meta else None

    @classmethod
    def open(
        cls,
        path: str | os.PathLike,
        config_hash: str,
        resume: bool = False,
        *,
        overwrite: bool = False,
        code_version_: str | None = None,
    ) -> "EvaluationStore":
        """Open the store of the study whose output folder (or database file) is ``path``.

        - No store yet: a fresh one is created (also when ``resume`` is True: there is nothing to resume,
          so the study starts from the beginning).
        - A store exists and ``resume`` is False: :class:`StoreExistsError`, unless ``overwrite`` is
          True, which deletes it and starts afresh.
        - A store exists and ``resume`` is True: it is reopened; if its config hash differs from
          ``config_hash``, :class:`ConfigChangedError`. A different code version only warns.
        """
        if not isinstance(config_hash, str) or not config_hash:
            raise ValueError("config_hash must be a non-empty string (see jointwear.compute.config_hash)")
        db = cls.db_path(path)
        version = code_version_ if code_version_ is not None else code_version()
        if db.exists() and not resume:
            if not overwrite:
                raise _exists_error(db)
            for suffix in ("", "-wal", "-shm", "-journal"):
                try:
                    os.remove(str(db) + suffix)
                except FileNotFoundError:
                    pass
        db.parent.mkdir(parents=True, exist_ok=True)
        conn = sqlite3.connect(str(db), timeout=30.0, isolation_level=None, check_same_thread=False)
        try:
            conn.execute("PRAGMA journal_mode=WAL")
            conn.execute("PRAGMA synchronous=FULL")
            conn.execute("BEGIN IMMEDIATE")
            for stmt in filter(None, (s.strip() for s in _SCHEMA.split(";"))):
                conn.execute(stmt)
            meta = dict(conn.execute("SELECT key, value FROM meta").fetchall())
            if "config_hash" not in meta:  # fresh (or killed before its first commit)
                mode = "fresh"
                conn.executemany(
                    "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)",
                    [
                        ("config_hash", config_hash),
                        ("code_version", version),
                        ("format", FORMAT_VERSION),
                        ("created_at", _now()),
                    ],
                )
            else:
                mode = "resume"
                problem = _meta_error(db, meta, config_hash)
                if problem is not None:
                    raise problem
                if meta.get("code_version") != version:
                    warnings.warn(
                        f"resuming a study written by jointwear {meta.get('code_version')} with "
                        f"{version}; stored calls are reused as they are",
                        stacklevel=2,
                    )
            conn.execute(
                "INSERT INTO sessions (opened_at, mode, code_version, pid) VALUES (?, ?, ?, ?)",
                (_now(), mode, version, os.getpid()),
            )
            conn.execute("COMMIT")
        except sqlite3.DatabaseError as exc:
            conn.close()
            if (damaged := _damaged_error(db, exc)) is not None:
                raise damaged from None
            raise
        except BaseException:
            if conn.in_transaction:
                conn.execute("ROLLBACK")
            conn.close()
            raise
        return cls(db, conn, config_hash, version)

    # -- context manager ----------------------------------------------------------------------------
    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def __enter__(self) -> "EvaluationStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"EvaluationStore({str(self.path)!r}, config_hash={self.config_hash[:12]}...)"

    @property
    def conn(self) -> sqlite3.Connection:
        if self._conn is None:
            raise StoreError("the evaluation store is closed")
        return self._conn

    # -- meta ---------------------------------------------------------------------------------------
    def meta(self) -> dict[str, str]:
        return dict(self.conn.execute("SELECT key, value FROM meta").fetchall())

    # -- calls --------------------------------------------------------------------------------------
    def put(self, tag: str, record: CallRecord) -> None:
        """Store one completed call and commit it at once."""
        x = np.asarray(record.x, dtype=np.float64).ravel()
        kind, names, blob = _encode_outputs(record.outputs)
        self.conn.execute(
            "INSERT INTO calls (tag, key, d, x, status, reason, out_kind, out_names, y, wall_s,"
            " started_at, finished_at, worker) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (
                tag,
                row_key(x),
                int(x.size),
                row_bytes(x),
                record.status,
                record.reason,
                kind,
                names,
                blob,
                float(record.wall_s),
                record.started_at,
                record.finished_at,
                record.worker,
            ),
        )  # autocommit mode (isolation_level=None): the row is committed when execute returns

    def get(self, tag: str, x: np.ndarray) -> CallRecord | None:
        """The stored call for the exact input row ``x`` (latest if several), or None."""
        return self.get_many(tag, [x])[0]

    def get_many(self, tag: str, rows: Iterable[np.ndarray]) -> list[CallRecord | None]:
        rows = [np.asarray(r, dtype=np.float64).ravel() for r in rows]
        out: list[CallRecord | None] = []
        cur = self.conn.cursor()
        for x in rows:
            xb = row_bytes(x)
            found = None
            for row in cur.execute(
                "SELECT x, status, reason, out_kind, out_names, y, wall_s, started_at, finished_at,"
                " worker FROM calls WHERE tag = ? AND key = ? ORDER BY id DESC",
                (tag, row_key(x)),
            ):
                if row[0] == xb:  # exact input, not only the same hash
                    found = CallRecord(
                        x=x.copy(),
                        status=row[1],
                        reason=row[2],
                        outputs=_decode_outputs(row[3], row[4], row[5]),
                        wall_s=row[6] if row[6] is not None else float("nan"),
                        started_at=row[7],
                        finished_at=row[8],
                        worker=row[9],
                    )
                    break
            out.append(found)
        return out

    def records(self, tag: str | None = None) -> list[CallRecord]:
        """All stored calls in the order they completed (of one tag, or all)."""
        q = (
            "SELECT x, status, reason, out_kind, out_names, y, wall_s, started_at, finished_at, worker"
            " FROM calls"
        )
        args: tuple = ()
        if tag is not None:
            q += " WHERE tag = ?"
            args = (tag,)
        q += " ORDER BY id"
        return [
            CallRecord(
                x=np.frombuffer(r[0], dtype="<f8").astype(np.float64),
                status=r[1],
                reason=r[2],
                outputs=_decode_outputs(r[3], r[4], r[5]),
                wall_s=r[6] if r[6] is not None else float("nan"),
                started_at=r[7],
                finished_at=r[8],
                worker=r[9],
            )
            for r in self.conn.execute(q, args)
        ]

    def __len__(self) -> int:
        return int(self.conn.execute("SELECT COUNT(*) FROM calls").fetchone()[0])

    def stats(self, tag: str | None = None) -> StoreStats:
        """Counts of stored calls (of one tag, or all); ``n_repeated`` must be 0."""
        where, args = ("WHERE tag = ?", (tag,)) if tag is not None else ("", ())
        n, n_ok, n_failed, n_timeout, wall = self.conn.execute(
            "SELECT COUNT(*), SUM(status = 'ok'), SUM(status = 'failed'), SUM(status = 'timeout'),"
            f" SUM(wall_s) FROM calls {where}",
            args,
        ).fetchone()
        n_rep = self.conn.execute(
            f"SELECT COALESCE(SUM(c - 1), 0) FROM (SELECT COUNT(*) AS c FROM calls {where}"
            " GROUP BY tag, x)",
            args,
        ).fetchone()[0]
        n_sessions = self.conn.execute("SELECT COUNT(*) FROM sessions").fetchone()[0]
        return StoreStats(
            n_calls=int(n or 0),
            n_ok=int(n_ok or 0),
            n_failed=int(n_failed or 0),
            n_timeout=int(n_timeout or 0),
            n_repeated=int(n_rep or 0),
            total_wall_s=float(wall or 0.0),
            n_sessions=int(n_sessions),
        )


def _damaged_error(db: Path, exc: sqlite3.Error) -> StoreError | None:
    """The error of a store file that is not a database or is damaged (named, without a traceback); None for any
    other sqlite error (a lock held past the timeout is not the file's fault)."""
    if getattr(exc, "sqlite_errorname", None) not in ("SQLITE_NOTADB", "SQLITE_CORRUPT"):
        return None
    return StoreError(f"the evaluation store {db} cannot be read ({exc}): move it away to start afresh "
                      "(--overwrite; overwrite=True in Python), or restore it")


def read_only_uri(db: str | os.PathLike) -> str:
    """SQLite's URI of ``db`` opened read-only: the path as a file URI, so that a '#', '?' or '%' in a folder's name
    (and a Windows drive or share) is not read as part of the URI."""
    return Path(db).resolve().as_uri() + "?mode=ro"
