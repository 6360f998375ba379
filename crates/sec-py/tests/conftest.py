from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
GOLDEN = REPO / "tests" / "golden"


@pytest.fixture
def golden():
    return GOLDEN


@pytest.fixture
def repo():
    return REPO
