"""Python values to `--set` texts."""

import numpy as np
import pytest

from chute._overrides import overrides


def test_values_become_toml_texts():
    got = overrides(
        {
            "a.int": 500,
            "a.float": 1e-3,
            "a.bool": True,
            "a.str": "corners",
            "a.list": [0.5, 1, "x"],
            "a.np": np.float64(2.5),
            "a.array": np.array([1.0, 2.0]),
            "a.inf": float("inf"),
            "a.table": [{"lines": [0], "start_s": 1.5}],
        }
    )
    assert got == [
        "a.int=500",
        "a.float=0.001",
        "a.bool=true",
        "a.str=corners",
        'a.list=[0.5, 1, "x"]',
        "a.np=2.5",
        "a.array=[1.0, 2.0]",
        "a.inf=inf",
        "a.table=[{lines = [0], start_s = 1.5}]",
    ]


def test_lists_of_texts_pass_through_and_bad_values_are_refused():
    assert overrides(["load.weight_n=20"]) == ["load.weight_n=20"]
    assert overrides(None) == []
    with pytest.raises(TypeError):
        overrides("load.weight_n=20")
    with pytest.raises(TypeError, match="object"):
        overrides({"a.b": object()})
