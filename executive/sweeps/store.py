"""The results store of a sweep: one SQLite file, one row per finished run, committed at once.

SQLite (the standard library's ``sqlite3``) rather than Parquet: a sweep appends one small row
at a time from one writer and must lose nothing when it is killed; each row is its own
transaction in write-ahead-log mode, so a killed sweep keeps every finished run and a resumed
one reads their ids back. Parquet files are written whole (a row group at a time) and would need
a log beside them for that. Reports read the rows with plain SQL.

Columns are split in two: the run's *record* (identity, parameters, outcome, reason, times,
recoveries, contacts, path length,
clearance, turning: byte-identical whichever executor ran it) and its *timing*
(wall time, worker, when, which invocation): these differ run to run and are documented as such.
"""

from __future__ import annotations

import json
import os
import sqlite3
import time
from typing import Any, Iterable

from executive.errors import ExecutiveError

RECORD_COLUMNS = ("run_id", "scenario", "seed", "tree", "point", "outcome", "reason", "passed",
                  "solved", "sim_time_s", "recoveries", "n_recoveries", "contacts",
                  "path_length_m", "min_clearance_m", "turning_rad_per_m", "goals_reached",
                  "goals_total", "error", "navbt_version")
TIMING_COLUMNS = ("wall_time_s", "worker", "finished_at", "session")

_SCHEMA = f"""
CREATE TABLE IF NOT EXISTS runs (
    run_id TEXT PRIMARY KEY,
    scenario TEXT NOT NULL, seed INTEGER NOT NULL, tree TEXT NOT NULL, point TEXT NOT NULL,
    outcome TEXT NOT NULL, reason TEXT, passed INTEGER, solved INTEGER, sim_time_s REAL,
    recoveries TEXT, n_recoveries INTEGER, contacts INTEGER, path_length_m REAL,
    min_clearance_m REAL, turning_rad_per_m REAL,
    goals_reached INTEGER, goals_total INTEGER, error TEXT, navbt_version TEXT,
    wall_time_s REAL, worker TEXT, finished_at REAL, session INTEGER
);
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS sessions (session INTEGER PRIMARY KEY, started_at REAL, planned INTEGER,
                                     skipped INTEGER);
"""


class StoreError(ExecutiveError, RuntimeError):
    """The results file cannot be opened or is not a navbt sweep store."""


class ResultStore:
    """Append-only store of finished runs (``results.sqlite`` in the sweep's output folder)."""

    FILE = "results.sqlite"

    def __init__(self, out_dir: str) -> None:
        os.makedirs(out_dir, exist_ok=True)
        self.path = out_dir if out_dir.endswith(".sqlite") else os.path.join(out_dir, self.FILE)
        try:
            self.db = sqlite3.connect(self.path, timeout=30.0)
            self.db.execute("PRAGMA journal_mode=WAL")
            self.db.execute("PRAGMA synchronous=NORMAL")   # WAL + NORMAL: durable per commit
            self.db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as e:
            raise StoreError(f"{self.path}: not a sweep results file ({e})") from None
        self.session = 0

    @classmethod
    def open_existing(cls, path: str) -> "ResultStore":
        """Open a store for reading (a folder holding results.sqlite, or the file itself)."""
        f = path if path.endswith(".sqlite") else os.path.join(path, cls.FILE)
        if not os.path.isfile(f):
            raise StoreError(f"{path}: no sweep results here (expected {cls.FILE})")
        return cls(os.path.dirname(f) if not path.endswith(".sqlite") else path)

    def begin(self, planned: int, skipped: int, spec_text: str | None = None) -> int:
        """Start an invocation of the sweep; returns its session number (1, 2, ...)."""
        row = self.db.execute("SELECT COALESCE(MAX(session), 0) FROM sessions").fetchone()
        self.session = int(row[0]) + 1
        with self.db:
            self.db.execute("INSERT INTO sessions VALUES (?, ?, ?, ?)",
                            (self.session, time.time(), planned, skipped))
            if spec_text is not None:
                self.db.execute("INSERT OR REPLACE INTO meta VALUES ('spec', ?)", (spec_text,))
        return self.session

    def set_meta(self, key: str, value: Any) -> None:
        with self.db:
            self.db.execute("INSERT OR REPLACE INTO meta VALUES (?, ?)", (key, json.dumps(value)))

    def meta(self, key: str, default: Any = None) -> Any:
        row = self.db.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()
        if row is None:
            return default
        try:
            return json.loads(row[0])
        except ValueError:
            return row[0]

    def finished_ids(self) -> set[str]:
        return {r[0] for r in self.db.execute("SELECT run_id FROM runs")}

    def add(self, record: dict[str, Any], timing: dict[str, Any]) -> None:
        """Write one finished run (its own transaction: it survives a kill right after)."""
        row = dict(record)
        row.update(timing)
        row.setdefault("session", self.session)
        row.setdefault("finished_at", time.time())
        for k in ("point", "recoveries"):
            if not isinstance(row.get(k), str):
                row[k] = json.dumps(row.get(k), sort_keys=True)
        cols = RECORD_COLUMNS + TIMING_COLUMNS
        with self.db:
            self.db.execute(f"INSERT OR IGNORE INTO runs ({', '.join(cols)}) VALUES "
                            f"({', '.join('?' for _ in cols)})", [row.get(c) for c in cols])

    def records(self, with_timing: bool = False) -> list[dict[str, Any]]:
        """Every run, ordered by id; ``point`` and ``recoveries`` decoded."""
        cols = RECORD_COLUMNS + (TIMING_COLUMNS if with_timing else ())
        out = []
        for r in self.db.execute(f"SELECT {', '.join(cols)} FROM runs ORDER BY run_id"):
            d = dict(zip(cols, r))
            d["point"] = json.loads(d["point"])
            d["recoveries"] = json.loads(d["recoveries"]) if d["recoveries"] else []
            out.append(d)
        return out

    def count(self, session: int | None = None) -> int:
        if session is None:
            return int(self.db.execute("SELECT COUNT(*) FROM runs").fetchone()[0])
        return int(self.db.execute("SELECT COUNT(*) FROM runs WHERE session = ?",
                                   (session,)).fetchone()[0])

    def close(self) -> None:
        self.db.close()


def records_equal(a: Iterable[dict[str, Any]], b: Iterable[dict[str, Any]]) -> bool:
    """Whether two stores hold the same records (timing columns aside)."""
    def norm(rs: Iterable[dict[str, Any]]) -> list[str]:
        return sorted(json.dumps({k: r[k] for k in RECORD_COLUMNS}, sort_keys=True) for r in rs)
    return norm(a) == norm(b)
