from pathlib import Path

import pytest

GOLDEN = Path(__file__).resolve().parents[3] / "tests" / "golden"


@pytest.fixture
def golden():
    return GOLDEN
