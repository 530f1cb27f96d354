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
