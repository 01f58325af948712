"""The same kind of script with two type errors, which mypy must report (so python:mypy can fail)."""
import nhc

scene = nhc.Scene.load("knife.toml")
run = scene.build("chetaev").simulate(t_end="2")   # a str for a float
count: str = len(run)                              # an int for a str
