"""A long refine run shows its progress (a bar on stderr naming the step and
the candidate) when asked, and the bar changes nothing in the result."""
from pysig.refine import Options, refine

from lab.studies.refine_cases import chamber_run, fit_data


def test_progress_names_the_candidates_and_changes_no_result(capsys):
    data = fit_data(chamber_run("thermal_lag", seed=3))
    quiet = refine(data, Options(progress=False)).report()
    assert capsys.readouterr().err == ""
    shown = refine(data, Options(progress=True, label="refine x")).report()
    err = capsys.readouterr().err
    assert "refine x" in err and "step 1: thermal_lag" in err and "fits" in err
    assert shown == quiet
