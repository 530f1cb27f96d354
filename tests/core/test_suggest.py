from btnav.core.suggest import best_match, close_matches


def test_close_spellings():
    assert (
        best_match("inflaton_radius", ["inflation_radius", "cost_scaling_factor"])
        == "inflation_radius"
    )
    assert best_match("zzz", ["inflation_radius"]) is None
    assert best_match("nav2_navfn_planner::NavfnPlanner", ["nav2_navfn_planner/NavfnPlanner"]) == (
        "nav2_navfn_planner/NavfnPlanner"
    )
    assert "nav2_behaviors/Spin" in close_matches(
        "Spin", ["nav2_behaviors/Spin", "nav2_behaviors/Wait"]
    )


def test_the_name_typed_is_never_suggested_back():
    """A lookup can miss a name that is among the candidates (another kind, another folder);
    "did you mean 'x'?" after typing x would help nobody."""
    assert best_match("Spin", ["Spin", "nav2_behaviors/Spin"]) == "nav2_behaviors/Spin"
    assert close_matches("odom", ["odom", "odm"]) == ["odm"]
    assert best_match("base_link", ["base_link"]) is None
