"""Global planners (NavFn, ...) and path smoothers."""
