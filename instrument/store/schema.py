"""The store's schema: its tables, as the migrations that build them, one version after another.

The version is SQLite's ``PRAGMA user_version``; migration n brings the schema from version n to
n + 1, and a store is migrated forward when it opens.
"""

from __future__ import annotations

import sqlite3

#: trial states; ``recording`` only while a writer is alive
TRIAL_STATUSES = ("recording", "recorded", "accepted", "rejected", "interrupted", "failed")

#: migration n brings the schema from version n to n + 1
MIGRATIONS: list[str] = [
    # v1: subjects, sessions, trials with one data file each
    """
    CREATE TABLE subjects (
        id INTEGER PRIMARY KEY,
        code TEXT NOT NULL UNIQUE,
        sex TEXT CHECK (sex IN ('female', 'male', 'other', 'unknown')),
        height_m REAL, mass_kg REAL, leg_length_m REAL,
        thigh_length_m REAL, shank_length_m REAL, hip_width_m REAL, foot_length_m REAL,
        thigh_circumference_m REAL, shank_circumference_m REAL,
        created_at REAL NOT NULL
    );
    CREATE TABLE sessions (
        id INTEGER PRIMARY KEY,
        subject_id INTEGER NOT NULL REFERENCES subjects(id),
        started_at REAL NOT NULL,
        operator TEXT, notes TEXT
    );
    CREATE TABLE trials (
        id INTEGER PRIMARY KEY,
        session_id INTEGER NOT NULL REFERENCES sessions(id),
        protocol TEXT NOT NULL,
        condition_json TEXT NOT NULL DEFAULT '{}',
        operator TEXT,
        trial_number INTEGER,
        status TEXT NOT NULL,
        reason TEXT,
        repeated_by INTEGER REFERENCES trials(id),
        file TEXT NOT NULL,
        started_at REAL NOT NULL, ended_at REAL,
        software_version TEXT,
        writer_host TEXT, writer_pid INTEGER
    );
    CREATE INDEX trials_session ON trials(session_id);
    """,
    # v2: files become their own table (a trial may have several: data, exports, plots) and
    # per-device sample counts are indexed so listing a store never opens a data file
    """
    CREATE TABLE trial_files (
        trial_id INTEGER NOT NULL REFERENCES trials(id),
        role TEXT NOT NULL,
        path TEXT NOT NULL,
        PRIMARY KEY (trial_id, role)
    );
    INSERT INTO trial_files (trial_id, role, path) SELECT id, 'data', file FROM trials;
    CREATE TABLE trial_devices (
        trial_id INTEGER NOT NULL REFERENCES trials(id),
        device TEXT NOT NULL,
        samples INTEGER NOT NULL DEFAULT 0,
        lost_samples INTEGER NOT NULL DEFAULT 0,
        gaps INTEGER NOT NULL DEFAULT 0,
        PRIMARY KEY (trial_id, device)
    );
    ALTER TABLE trials DROP COLUMN file;
    """,
    # v3: operators are stored once, by name, and referenced everywhere else (trial files,
    # exports, the trial index) by a code
    """
    CREATE TABLE operators (
        code TEXT PRIMARY KEY,
        name TEXT NOT NULL UNIQUE,
        created_at REAL NOT NULL
    );
    """,
    # v4: analysis results, keyed by a hash of everything that decides them (trials' data,
    # settings, method version), with the inputs (trial ids, file SHA-256) they were made from
    """
    CREATE TABLE analysis_results (
        key TEXT PRIMARY KEY,
        kind TEXT NOT NULL,
        subject_code TEXT,
        label TEXT,
        inputs_json TEXT NOT NULL,
        settings_json TEXT NOT NULL,
        versions_json TEXT NOT NULL,
        result_json TEXT NOT NULL,
        created_at REAL NOT NULL
    );
    CREATE INDEX analysis_results_kind ON analysis_results(kind, subject_code);
    """,
]
SCHEMA_VERSION = len(MIGRATIONS)


def statements(script: str) -> list[str]:
    """The SQL statements of a migration script, one by one (``executescript`` would commit)."""
    out, buf = [], ""
    for line in script.splitlines(keepends=True):
        buf += line
        if sqlite3.complete_statement(buf):
            if buf.strip().strip(";").strip():
                out.append(buf.strip())
            buf = ""
    if buf.strip():
        out.append(buf.strip())
    return out


__all__ = ["MIGRATIONS", "SCHEMA_VERSION", "TRIAL_STATUSES", "statements"]
