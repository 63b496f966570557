"""Study files and the parameter registry (moorline.studies): what a study may say, the clear
errors for what it may not, the registry's setters, and the case keys that resume relies on."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from moorline.io import read_deck
from moorline.studies import PARAMETERS, Study, StudyError, register_parameter
from moorline.studies.parameters import _apply_parameters

HERE = Path(__file__).resolve().parent
DECK = HERE / "tiny_cable.dat"
SCATTER = HERE.parents[1] / "examples" / "w4p_study" / "w4p_scatter.csv"


def study(tmp_path=None, **kw):
    d = {"deck": str(DECK), "sea_states": {"Hs": 1.0, "Tz": 4.0},
         "post": {"section": {"do": 0.04, "di": 0.02}, "sn": {"alpha": 6.098e19, "m": 6.238, "unit": 1e6}}}
    d.update(kw)
    return Study.from_dict(d, base_dir=tmp_path or HERE)


def test_grid_cases_in_order_with_stable_keys():
    st = study(parameters={"mass": [2.0, 6.0], "EI": [50, 200, 350]})
    specs = st.case_specs()
    assert [s.params for s in specs[:4]] == [{"mass": 2.0, "EI": 50}, {"mass": 2.0, "EI": 200},
                                             {"mass": 2.0, "EI": 350}, {"mass": 6.0, "EI": 50}]
    assert len({s.key for s in specs}) == 6
    assert [s.key for s in study(parameters={"mass": [2.0, 6.0], "EI": [50, 200, 350]}).case_specs()] == \
        [s.key for s in specs]
    # a different setting changes every key
    other = study(parameters={"mass": [2.0, 6.0], "EI": [50, 200, 350]}, simulation={"samples_per_period": 30})
    assert not {s.key for s in other.case_specs()} & {s.key for s in specs}


def test_key_follows_the_deck_contents_not_its_path(tmp_path):
    shutil.copy(DECK, tmp_path / "deck.dat")
    a = study(parameters={"mass": [2.0]}).case_specs()[0].key
    b = Study.from_dict({"deck": "deck.dat", "sea_states": {"Hs": 1.0, "Tz": 4.0},
                         "post": {"section": {"do": 0.04, "di": 0.02},
                                  "sn": {"alpha": 6.098e19, "m": 6.238, "unit": 1e6}},
                         "parameters": {"mass": [2.0]}}, base_dir=tmp_path).case_specs()[0].key
    assert a == b
    (tmp_path / "deck.dat").write_text((tmp_path / "deck.dat").read_text().replace("20.0      5", "21.0      5"))
    c = Study.from_dict({"deck": "deck.dat", "sea_states": {"Hs": 1.0, "Tz": 4.0},
                         "post": {"section": {"do": 0.04, "di": 0.02},
                                  "sn": {"alpha": 6.098e19, "m": 6.238, "unit": 1e6}},
                         "parameters": {"mass": [2.0]}}, base_dir=tmp_path).case_specs()[0].key
    assert c != a


def test_setters_change_the_model():
    m = read_deck(DECK)
    sea = _apply_parameters(m, {"mass": 6.0, "EI[cable]": 50.0, "length": 25.0, "segments": 7, "Hs": 2.0,
                                "wave_heading": 30.0})
    lt = m.line_types["cable"]
    assert (lt.w, lt.EI, m.lines[0].L, m.lines[0].N) == (6.0, 50.0, 25.0, 7)
    assert sea == {"Hs": 2.0, "heading": 30.0}


@pytest.mark.parametrize("params, match", [
    ({"colour": [1]}, "unknown parameter 'colour'; known parameters: .*mass"),
    ({"current_speed[1]": [1.0]}, "current parameters take no \\[target\\]"),
    ({"current_speed": [-1.0]}, "current: current speed must be >= 0"),
    ({"mass[chain]": [1.0]}, "no line type 'chain'"),
    ({"length[3]": [1.0]}, "no line '3'"),
    ({"Hs[1]": [1.0]}, "take no \\[target\\]"),
])
def test_parameter_errors_name_the_parameter(params, match):
    with pytest.raises(StudyError, match=match):
        study(parameters=params)


def test_study_errors():
    with pytest.raises(StudyError, match="unknown key.*colour"):
        study(colour=1)
    with pytest.raises(StudyError, match="Hs and Tz come from the scatter"):
        study(sea_states={"scatter": str(SCATTER)}, parameters={"Hs": [1.0]})
    with pytest.raises(StudyError, match="'duration'"):
        study(sea_states=None)
    with pytest.raises(StudyError, match="line 2"):
        study(line=2)
    with pytest.raises(StudyError, match="post.sn needs post.section"):
        study(post={"sn": {"alpha": 1e10, "m": 3}})
    with pytest.raises(StudyError, match="'alpha' is required"):
        study(post={"section": {"do": 0.04}, "sn": {"m": 3}})
    with pytest.raises(StudyError, match="either 'parameters'"):
        study(parameters={"mass": [1.0]}, cases=[{"mass": 2.0}])
    with pytest.raises(StudyError, match="not found"):
        study(deck="missing.dat")


def test_current_parameters_make_one_uniform_current():
    """current_speed and current_heading are applied together, in any order; one of them alone
    keeps the other from the deck's uniform current; a current varying in space cannot be."""
    from moorline.model.water import Current

    for params in ({"current_heading": 90.0, "current_speed": 1.5}, {"current_speed": 1.5, "current_heading": 90.0}):
        m = read_deck(DECK)
        _apply_parameters(m, params)
        np.testing.assert_allclose(m.env.current.velocity.reshape(3), [0.0, 1.5, 0.0], atol=1e-15)
    m = read_deck(DECK)
    m.env.current = Current.uniform(2.0, 180.0)
    _apply_parameters(m, {"current_speed": 0.5})
    np.testing.assert_allclose(m.env.current.velocity.reshape(3), [-0.5, 0.0, 0.0], atol=1e-15)
    m.env.current = Current.profile([-15.0, 0.0], [0.0, 1.0])
    with pytest.raises(StudyError, match="varies in space or time"):
        _apply_parameters(m, {"current_heading": 10.0})


def test_fixed_parameters_apply_to_every_case():
    st = study(fixed={"current_speed": 1.0, "mass[cable]": 3.0}, parameters={"EI": [50.0, 350.0]})
    assert [s.params for s in st.case_specs()] == [{"EI": 50.0}, {"EI": 350.0}]
    assert st.case_specs()[0].settings["fixed"] == {"current_speed": 1.0, "mass[cable]": 3.0}
    with pytest.raises(StudyError, match="EI: both fixed and varied"):
        study(fixed={"EI": 1.0}, parameters={"EI": [50.0]})
    with pytest.raises(StudyError, match="unknown parameter 'colour'"):
        study(fixed={"colour": 1})


def test_register_parameter_extends_the_registry():
    """A new named setter: one call, then studies may use it."""
    try:
        register_parameter("seabed_stiffness", lambda model, value, target=None: setattr(model.env, "kBot", value),
                           units="Pa/m", doc="seabed contact stiffness")
        st = study(parameters={"seabed_stiffness": [1e6]})
        m = read_deck(DECK)
        _apply_parameters(m, st.case_specs()[0].params)
        assert m.env.kBot == 1e6
    finally:
        PARAMETERS.pop("seabed_stiffness", None)


@pytest.mark.parametrize("kind", ["regular", "jonswap"])
def test_sea_waves_are_in_phase_with_the_buoy(kind):
    """The waves put on the lines for a sea state have, at the buoy (here at x = 10, y = 5 m, waves
    heading 30 deg), the elevation the buoy heaves with, ramp included."""
    from moorline.post import SeaState, buoy_motion, wavenumber
    from moorline.studies import sea_waves

    sea = SeaState(2.0, 6.0, kind=kind, heading=30.0, seed=3)
    x0 = np.array([10.0, 5.0, -2.0])
    labels = ["P1_x", "P1_y", "P1_z"]
    t, X = buoy_motion(sea, x0, duration=60.0, dt=0.1, depth=50.0, ramp=12.0, labels=labels)
    wv = sea_waves(sea, x0, labels, depth=50.0, g=9.80665, ramp=12.0, duration=60.0)
    assert wv.ramp_time == 12.0
    k = wavenumber(wv.omega, 50.0)
    lb = 10.0 * np.cos(np.radians(30.0)) + 5.0 * np.sin(np.radians(30.0))
    zeta = np.cos(np.outer(t, wv.omega) - k * lb + np.angle(wv.amplitude)) @ np.abs(wv.amplitude)
    ramp = 0.5 * (1 - np.cos(np.pi * np.clip(t / 12.0, 0, 1)))
    np.testing.assert_allclose(zeta * ramp, X[:, 2] + 2.0, atol=1e-9)
