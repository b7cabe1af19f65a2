"""The MCU cost figures model choice uses (pysig.tcomp._cost) are the ones
bench/model_pareto.py measured: the library keeps a small table so it never
reads a bench file at run time, and this test keeps the table true to the
bench's JSON."""
import json
import statistics

import pytest

from conftest import ROOT
from pysig.tcomp import _cost

PARETO_JSON = ROOT / "bench" / "model_pareto" / "results" / "model_pareto.json"


@pytest.fixture(scope="module")
def rows():
    return json.loads(PARETO_JSON.read_text())["rows"]


def test_polynomial_cycles_are_the_measured_medians(rows):
    for order, cycles in _cost.POLY_CYCLES.items():
        measured = [r["cycles"] for r in rows if r["family"] == "poly" and r["size"] == order]
        assert measured, f"the bench measured no order-{order} polynomial"
        assert cycles == round(statistics.median(measured)), order


def test_table_cycles_are_the_measured_median(rows):
    measured = [r["cycles"] for r in rows if r["family"] == "pwl"]
    assert _cost.TABLE_CYCLES == round(statistics.median(measured))


def test_code_and_data_bytes_are_the_measured_ones(rows):
    for family, ours in (("poly", "poly"), ("pwl", "table")):
        text = {r["text_bytes"] for r in rows if r["family"] == family}
        assert len(text) == 1
        for r in rows:
            if r["family"] == family:
                c = _cost.cost(ours, r["size"])
                assert (c.text_bytes, c.data_bytes) == (r["text_bytes"], r["data_bytes"]), r
