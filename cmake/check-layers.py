#!/usr/bin/env python3
"""Checks the layering of the selfcalib module (doc/architecture.md, "Layers"): each layer depends
only on those before it, so a file may include files of its own topic and of layers of a lower rank,
never of a higher rank:

    core (0) < kinematics, twoview (1) < reconstruction, scale (2) < identification (3)
    < planning, validation (4) < pipeline (5) < protocol (6) < simulation, frontend, io (7)
    < acquisition (8)

(validation: the data check and the verification, which the pipeline runs; protocol: what runs the
pipeline, cross-validation, the pose study and the calibrate-then-cross-validate protocol.)

(acquisition drives a robot and writes datasets: it uses io, and simulation for its rendering grabber.)

Topics of one rank do not include each other either ("sideways"), except where SIDEWAYS_ALLOWED
says why.

    cmake/check-layers.py [MODULE_DIR]      (default: modules/selfcalib beside this script)

src/<topic>/ files are in their topic; a public header is in the topic of the source file of the
same name (vpKinematicChain.h: src/kinematics/vpKinematicChain.cpp), unless HEADER_TOPIC places it.
Includes of files outside the module are not checked. Prints every include that breaks the rule,
and the allowed sideways ones; the exit status is 1 when something breaks it, 2 when a header
cannot be placed.
"""
import os
import re
import sys

RANK = {
    'core': 0,
    'kinematics': 1, 'twoview': 1,
    'reconstruction': 2, 'scale': 2,
    'identification': 3,
    'planning': 4, 'validation': 4,
    'pipeline': 5,
    'protocol': 6,
    'simulation': 7, 'frontend': 7, 'io': 7,
    'acquisition': 8,
}
# Public headers with no source file of their name, or whose type belongs higher than the file
# that implements part of it.
HEADER_TOPIC = {
    'vpSelfCalibException.h': 'core',  # the module's exception, used by every layer
    'vpSelfCalibExport.h': 'core',     # the export macro of every public class
    'vpSelfCalibDataset.h': 'core',    # the data every layer reads; its YAML methods are in io
    'vpDotGrid.h': 'core',             # a dot target's description: drawn in simulation, found in frontend
    'vpPlannerScene.h': 'planning',    # the planner's input, filled by the simulator
}
# (from topic, to topic): why a topic may include another of the same layer.
SIDEWAYS_ALLOWED = {
    ('io', 'frontend'): "the report presents the front end's statistics (DESIGN.md places io after the front end)",
}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def module_files(module):
    """(path relative to the module, topic or None for public headers) of every C++ file."""
    out = []
    src = os.path.join(module, 'src')
    for topic in sorted(os.listdir(src)):
        for name in sorted(os.listdir(os.path.join(src, topic))):
            if name.endswith(('.h', '.cpp')):
                out.append((os.path.join('src', topic, name), topic))
    inc = os.path.join('include', 'visp3', 'selfcalib')
    for name in sorted(os.listdir(os.path.join(module, inc))):
        if name.endswith('.h'):
            out.append((os.path.join(inc, name), None))
    return out


def header_topics(files):
    """Topic of every public header; a header that cannot be placed is reported and exits."""
    sources = {os.path.basename(p)[:-len('.cpp')]: t for p, t in files if t and p.endswith('.cpp')}
    topics, unplaced = {}, []
    for path, topic in files:
        if topic is not None:
            continue
        name = os.path.basename(path)
        topics[name] = HEADER_TOPIC.get(name) or sources.get(name[:-len('.h')])
        if topics[name] is None:
            unplaced.append(path)
    if unplaced:
        print('cannot place these public headers in a layer (add them to HEADER_TOPIC):')
        for p in unplaced:
            print('  ' + p)
        sys.exit(2)
    return topics


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    module = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, '..', 'modules', 'selfcalib')
    files = module_files(module)
    headers = header_topics(files)
    topic_of = {p: t for p, t in files if t}
    topic_of.update({os.path.join('include', 'visp3', 'selfcalib', n): t for n, t in headers.items()})
    broken, allowed, count = [], [], 0
    for path, _ in files:
        source_topic = topic_of[path]
        with open(os.path.join(module, path), encoding='utf-8') as f:
            for line_number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                if m.group(2).startswith('visp3/selfcalib/'):
                    target = os.path.join('include', m.group(2))
                elif m.group(1) == '"':
                    target = os.path.normpath(os.path.join(os.path.dirname(path), m.group(2)))
                else:
                    continue
                if target not in topic_of:
                    continue
                count += 1
                to = topic_of[target]
                where = '%s:%d: %s (%d) includes %s: %s (%d)' % (path, line_number, source_topic, RANK[source_topic],
                                                                  os.path.basename(target), to, RANK[to])
                if to == source_topic or RANK[to] < RANK[source_topic]:
                    continue
                if RANK[to] == RANK[source_topic] and (source_topic, to) in SIDEWAYS_ALLOWED:
                    allowed.append(where + ' [allowed: ' + SIDEWAYS_ALLOWED[(source_topic, to)] + ']')
                else:
                    broken.append(where + (' [higher rank]' if RANK[to] > RANK[source_topic] else ' [sideways]'))
    print('layering of %s: %d files, %d includes within the module' % (os.path.normpath(module), len(files), count))
    for w in allowed:
        print('  ' + w)
    if broken:
        print('%d include(s) break the layering:' % len(broken))
        for w in broken:
            print('  ' + w)
        return 1
    print('no include breaks the layering')
    return 0


if __name__ == '__main__':
    sys.exit(main())
