"""`make demo` (`python -m fuzzyc.demo`): the main job on the shipped rule bases, end to end."""
