"""Shared fixtures; hardware tests are opt-in with --device-url (never needed in CI)."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# one BLAS thread per worker: three workers on two cores with OpenBLAS's threads each spend time switching, not
# solving (four diagnoses 26.7 s with its threads, 18.7 s with one, measured once on this 2-core host beside another
# run; quiet, six diagnoses took 7.9 s either way); the variables reach the subprocesses (OpenSim, fitting workers),
# threadpoolctl the BLAS a plugin may have loaded before this file
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
try:
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)
except ImportError:  # pragma: no cover - threadpoolctl comes with the test extra
    pass
# the suite already runs three workers on two cores: a model-level diagnosis spawning two more fitting
# processes only adds contention and interpreter start-ups (one test asks for two workers explicitly)
os.environ.setdefault("INSTRUMENT_FIT_WORKERS", "1")
# liblsl's warnings only (the instrument's own setting; tests that import pylsl first would get INFO lines)
os.environ.setdefault("LSLAPICFG", os.path.join(os.path.dirname(__file__), "..", "drivers", "lsl", "lsl_api.cfg"))


#: files whose tests stand alone and take minutes each: they may run on different workers. Every other
#: file's tests run on one worker, in order, as with ``--dist loadfile`` (module fixtures such as the demo's
#: run once; LSL stream names and ports are not shared between a file's tests at the same moment)
SPLIT_FILES = ("tests/analysis/test_pmp_model_diagnosis.py", "tests/analysis/test_pmp_opensim_truth.py",
               "tests/instrument/test_analyses.py", "tests/analysis/test_diagnosis_independent.py")
#: handed to the workers first (the longest units), so that no long unit starts last and leaves one
#: worker idle; xdist keeps this order with ``--no-loadscope-reorder``
FIRST_FILES = ("tests/instrument/test_demo.py", *SPLIT_FILES)


def _file_of(nodeid: str) -> str:
    return nodeid.split("::")[0]


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    rank = {f: i for i, f in enumerate(FIRST_FILES)}
    items.sort(key=lambda item: rank.get(_file_of(item.nodeid), len(rank)))  # stable: a file's own order kept


@pytest.hookimpl(optionalhook=True)  # a hook of pytest-xdist's: without xdist (``-p no:xdist``) it is not called
def pytest_xdist_make_scheduler(config: pytest.Config, log: object) -> object:
    """The workers' units: a file, or one test of :data:`SPLIT_FILES` (xdist's ``loadgroup`` would say this
    with marks, but it renames node ids, which pytest 9 no longer lets it do)."""
    from xdist.scheduler import LoadScopeScheduling

    class FilesWithHeavyTestsSplit(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return nodeid if _file_of(nodeid) in SPLIT_FILES else _file_of(nodeid)

    return FilesWithHeavyTestsSplit(config, log)


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--device-url", action="append", default=[],
                     help="URL of a real device for the *_with_device tests (repeatable)")


@pytest.fixture
def device_urls(request: pytest.FixtureRequest) -> list[str]:
    urls = request.config.getoption("--device-url")
    if not urls:
        pytest.skip("hardware test: pass --device-url to run it")
    return urls
