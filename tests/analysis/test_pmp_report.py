"""The passive-parameter report's figures: fit per trial, and Figures 3.15–3.17 against the generic model."""

from __future__ import annotations

from pathlib import Path

from analysis.pmp.report import _fit_figure, _parameter_figure, analyse, text, to_json, write_plots
from analysis.pmp.synthetic import simulated_subject


def test_report_writes_the_fit_and_the_three_parameter_panels(tmp_path: Path) -> None:
    _, trials, subject = simulated_subject(2, ("knee", "ankle"))
    report = analyse([trials[0], trials[3]], subject, intervals=10)
    files = write_plots(report, tmp_path)
    assert [f.name for f in files] == ["pmp_fit.png", "pmp_parameters.png", "pmp_report.json"]
    assert all(f.stat().st_size > 5000 for f in files[:2])
    fig = _parameter_figure(report)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles == ["tendon slack length (Fig. 3.15)", "tendon stiffness (Fig. 3.16)", "muscle stiffness (Fig. 3.17)"]
    # every free parameter has a bar pair (generic, fitted) in its panel
    n_slack = sum(n.endswith("tendon_slack_length_m") for n in report.result.parameters)
    assert len(fig.axes[0].patches) == 2 * n_slack
    assert "leg" not in to_json(report)


def test_a_named_extension_is_fitted_directly_without_the_diagnosis() -> None:
    """What an earlier ``--diagnose-model`` named is refitted by name: a 1.5 N·m arm-weight error on every trial
    is found as the ankle's offset (its muscles cannot make a constant torque; the knee's partly absorb it, so
    only the ankle's is held to its value) and the residual falls."""
    import dataclasses

    import pytest

    from analysis.errors import InputError

    _, trials, subject = simulated_subject(3, ("knee", "ankle"))
    offset = [dataclasses.replace(t, torque_nm=t.torque_nm + 1.5) for t in trials]
    with pytest.raises(InputError, match="no model extension 'friction'"):
        analyse(offset, subject, intervals=10, extension="friction")  # refused before any fit
    report = analyse(offset, subject, intervals=10, extension="torque_offset")
    ext = report.extended
    assert ext is not None and ext.extension == "torque_offset" and report.model_diagnosis is None
    # the offset's moment toward positive angles opposes the dynamometer's added torque
    assert abs(ext.parameters["ankle_offset_Nm"] + 1.5) < 0.3
    assert ext.misfit_ratio < ext.plain_misfit_ratio - 0.2
    # a plain report that misfits points at the model-level diagnosis; one already extended does not
    misfit = dataclasses.replace(report.identifiability, model_misfit=True, determined=[],
                                 not_determined_because=["the model does not fit the data well enough"])
    plain_text = text(dataclasses.replace(report, extended=None, identifiability=misfit))
    assert "next: the muscle model lacks something" in plain_text and "--diagnose-model" in plain_text
    assert "end range structures" in plain_text and "next:" not in text(dataclasses.replace(report, identifiability=misfit))
    # how much of each parameter's effect the offset's terms reproduce (R²), every parameter's; one told from them by
    # the curves' shapes only is said to be, with what would separate them
    shares = report.identifiability.extension_share
    assert set(shares) == set(report.result.parameters) and all(0.0 <= v <= 1.0 for v in shares.values())
    assert max(shares.values()) > 0.0
    assert "shapes only" not in text(report) or any(shares[n] > 0.9 for n in report.identifiability.determined)
    if report.identifiability.determined:
        name = report.identifiability.determined[0]
        shape_only = dataclasses.replace(report.identifiability, extension_share={**shares, name: 0.95})
        line = next(x for x in text(dataclasses.replace(report, identifiability=shape_only)).splitlines()
                    if "shapes only" in x)
        assert f"95 % of {name}'s effect" in line and "an offset needs a return sweep" in line
    # its share is drawn in every trial's torque panel and named in that panel's legend
    torque_panels = _fit_figure(report).axes[: len(offset)]
    assert all("torque_offset (its share)" in [t.get_text() for t in ax.get_legend().get_texts()]
               for ax in torque_panels)


def test_a_plausible_model_beside_the_named_one_is_fitted_and_its_estimates_held_by_the_intervals(monkeypatch) -> None:
    """When the held-out test leaves a model plausible (better on every fold, by less than the margin), the report
    fits it and reports the hull of the intervals: every interval holds its own, and the parameters determined are
    those both models determine (the diagnosis stubbed: it names nothing and leaves a tonic activation plausible)."""
    import dataclasses

    import analysis.pmp.model_diagnosis as md

    _, trials, subject = simulated_subject(11, ("knee",))
    # the simulated subject's anthropometry is exact (the model made the trials): no measurement uncertainty
    subject = dataclasses.replace(subject, shank_length_sd_m=0.0, set_angle_sd_rad=0.0, mass_sd_kg=0.0)
    plain = analyse(trials, subject, intervals=12)
    monkeypatch.setattr(md, "diagnose_model", lambda *a, **k: md.ModelDiagnosis(
        "none", 0.3, {}, [], "no extension predicts better", ["blocks 1"], plausible=["tonic_activation"]))
    report = analyse(trials, subject, intervals=12, diagnose_model=True)
    idf = report.identifiability
    assert idf.model_alternatives == ["tonic_activation"] and "hull" in idf.uncertainty
    assert set(idf.determined) <= set(plain.identifiability.determined) and idf.determined
    for name in idf.determined:
        lo, hi = idf.ci95[name]
        plain_lo, plain_hi = plain.identifiability.ci95[name]
        assert lo <= plain_lo + 1e-12 and hi >= plain_hi - 1e-12
