"""Errors as Python users expect them: a bad file, a wrong-shaped array, an unknown param, a NaN
param each raise an exception naming it; none ends the interpreter."""

import re

import numpy as np
import pytest

import mechgen


def test_a_bad_file_raises_value_error_with_every_diagnostic(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[mechanism.m]\ninputs = ["q1"]\nunknowns = ["q2", "q3"]\nloops = ["l1*e(q1) + zz"]\n')
    with pytest.raises(ValueError) as e:
        mechgen.load(str(bad))
    assert re.search(r"bad\.toml:\d+:\d+", str(e.value)), str(e.value)
    assert "zz" in str(e.value)


def test_a_missing_file_raises_value_error_naming_it(tmp_path):
    with pytest.raises(ValueError, match="nothing.toml"):
        mechgen.load(str(tmp_path / "nothing.toml"))


def test_arrays_of_different_lengths_raise_value_error():
    m = mechgen.mechanisms()["four_bar"]
    with pytest.raises(ValueError, match="l2"):
        m.batch({"l1": np.array([0.1, 0.11]), "l2": np.array([0.35])})


def test_a_two_dimensional_array_raises():
    m = mechgen.mechanisms()["four_bar"]
    with pytest.raises((ValueError, TypeError)):
        m.batch({"l1": np.ones((2, 2)) * 0.1})


def test_an_unknown_param_raises_key_error_naming_it():
    m = mechgen.mechanisms()["four_bar"]
    with pytest.raises(KeyError, match="nope"):
        m.batch({"nope": np.array([1.0])})
    with pytest.raises(KeyError, match="nope"):
        m.sweep(params={"nope": 1.0})


def test_a_nan_param_raises_value_error_naming_it():
    m = mechgen.mechanisms()["four_bar"]
    with pytest.raises(ValueError, match="l3"):
        m.batch({"l3": np.array([0.3, np.nan])})
    with pytest.raises(ValueError, match="start"):
        m.sweep(start=float("nan"))


def test_an_unknown_input_and_holding_the_swept_input_raise_value_error():
    m = mechgen.mechanisms()["four_bar"]
    with pytest.raises(ValueError, match="no input `zz`"):
        m.sweep(input="zz")
    with pytest.raises(ValueError, match="swept input"):
        m.sweep(set={"q1": 10.0})


def test_a_derived_param_raises_value_error_naming_its_bases(tmp_path):
    f = tmp_path / "derived.toml"
    f.write_text(
        '[mechanism.m]\ninputs = ["q1"]\nunknowns = ["q2", "s"]\n'
        'loops = ["r*e(q1) + l*e(q2) - c(s, 0)"]\n'
        '[mechanism.m.params]\nr = 0.1\nl = "4*r"\n'
        '[mechanism.m.start]\nq1 = 0.0\nq2 = 0.0\ns = 0.5\n'
    )
    m = mechgen.load(str(f))["m"]
    assert list(m.params) == ["r"]
    with pytest.raises(ValueError, match="derived"):
        m.batch({"l": [0.3]})
    assert m.batch({"r": [0.1, 0.12]})["status"].shape == (2, 37)


def test_messages_name_keyword_arguments_not_command_line_options():
    m = mechgen.mechanisms()["four_bar"]
    for call, word in [
        (lambda: m.sweep(step=0.0), "step must not be zero"),
        (lambda: m.sweep(set={"q1": 10.0}), "use from/to, or input to sweep another"),
        (lambda: m.sweep(set={"l1": 0.2}), "`l1` is a param: give its value with `params=`"),
    ]:
        with pytest.raises(ValueError, match=word) as e:
            call()
        assert "--" not in str(e.value)
    with pytest.raises(KeyError, match="`l1` is a param: give its value with `params=`") as e:
        m.simulate(time=0.1, dt=0.01, input="l1")
    assert "--" not in str(e.value)
    s = mechgen.mechanisms()["shaper"]
    with pytest.raises(ValueError, match="time needs a value") as e:
        s.simulate(time=-1.0, dt=0.1)
    assert "--" not in str(e.value)
