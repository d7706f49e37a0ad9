"""The session store, one job per module: the index (``index``), its schema and migrations
(``schema``), subjects and trial records (``records``), analysis results (``results``), recovery of
interrupted trials (``recovery``), the writer's lock (``lock``), the disk reserve (``reserve``) and
file hashes (``hashing``)."""

from __future__ import annotations

from .hashing import file_sha256, software_versions
from .index import SessionStore, default_store_dir, open_store
from .lock import TrialLock
from .records import DEFAULT_SUBJECT_CODE_PATTERN, Subject, TrialRecord, check_subject_code, subject_code_pattern
from .reserve import RESERVE_BYTES
from .results import analysis_key, remembered, trial_inputs
from .schema import MIGRATIONS, SCHEMA_VERSION, TRIAL_STATUSES

__all__ = ["DEFAULT_SUBJECT_CODE_PATTERN", "MIGRATIONS", "RESERVE_BYTES", "SCHEMA_VERSION", "TRIAL_STATUSES",
           "SessionStore", "Subject", "TrialLock", "TrialRecord", "analysis_key", "check_subject_code",
           "default_store_dir", "file_sha256", "open_store", "remembered", "software_versions",
           "subject_code_pattern", "trial_inputs"]
