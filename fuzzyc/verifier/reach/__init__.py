"""Sound reachable sets of closed loops (`fuzzyc verify --prove`): affine forms through the
whole chain (plant, observers, controller), decided against the temporal checks."""
