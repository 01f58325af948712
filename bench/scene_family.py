"""What the benchmarks' scalable scene families (knife_chain.py, particle_chain.py,
rolling_balls.py) write alike: the [parameters] and [simulate] tables, and the command line that
writes OUTDIR/<family>_<N>.toml for each N (atomically: a .tmp file renamed)."""
import os
import sys

LARGEST_N = 1024


def parameters_table(parameters):
    """[parameters] lines from (name, value) pairs, in order."""
    return ["[parameters]"] + ["%s = %r" % (name, value) for name, value in parameters]


def simulate_table(t_end, rtol, atol, model="chetaev"):
    """[simulate] lines."""
    return ["[simulate]", 'model = "%s"' % model, "t_end = %r" % t_end, "rtol = %r" % rtol, "atol = %r" % atol]


def write_scenes(argv, family, scene_text):
    """`family.py OUTDIR N [N ...]` (argv as sys.argv): writes each scene; returns the exit code."""
    if len(argv) < 3:
        sys.stderr.write("usage: %s.py OUTDIR N [N ...]\n" % family)
        return 2
    outdir = argv[1]
    os.makedirs(outdir, exist_ok=True)
    for arg in argv[2:]:
        n = int(arg)
        if not 1 <= n <= LARGEST_N:
            sys.stderr.write("%s.py: N must be in 1..%d, got %d\n" % (family, LARGEST_N, n))
            return 2
        path = os.path.join(outdir, "%s_%d.toml" % (family, n))
        with open(path + ".tmp", "w") as f:
            f.write(scene_text(n))
        os.replace(path + ".tmp", path)
    return 0
