#!/usr/bin/env python3
"""The module graph holds: every #include "x/y.h" of a library under src/ names a header of a
library it links (itself included), and no two libraries link each other. The graph is the
build's own (cmake/architecture.cmake writes BUILD/module_graph.tsv); ARCHITECTURE.md explains it.

usage: architecture_check.py SOURCE_DIR BUILD_DIR
"""
import os
import re
import sys

# Links the design forbids (ARCHITECTURE.md, "Rules"): library -> libraries it must not reach.
FORBIDDEN = {
    # What users link to predict carries no training, evaluation or dataset-reading code.
    "motionfork_api": ["motionfork_generator_training", "motionfork_eval",
                       "motionfork_imputation_training", "motionfork_denoise_training"],
    "motionfork_pipeline": ["motionfork_generator_training", "motionfork_eval",
                            "motionfork_imputation_training", "motionfork_denoise_training"],
    # Model modules take options structs; reading YAML and bundles is the layers above.
    "motionfork_flow": ["motionfork_config", "motionfork_bundle"],
    "motionfork_refine": ["motionfork_config", "motionfork_bundle", "motionfork_dataset"],
    "motionfork_imputation": ["motionfork_config", "motionfork_bundle"],
    "motionfork_denoise": ["motionfork_config", "motionfork_bundle"],
    "motionfork_generator_model": ["motionfork_config", "motionfork_bundle"],
    "motionfork_generator_trajectory": ["motionfork_config", "motionfork_bundle",
                                        "motionfork_dataset", "motionfork_eval"],
    # The data modules below the config layer do not read YAML.
    "motionfork_core": ["motionfork_config"],
    "motionfork_io": ["motionfork_config"],
    "motionfork_dataset": ["motionfork_config"],
    "motionfork_eval": ["motionfork_config"],
    # The config layer includes no model.
    "motionfork_config": ["motionfork_flow", "motionfork_refine", "motionfork_imputation",
                          "motionfork_denoise",
                          "motionfork_generator_model", "motionfork_generator_trajectory",
                          "motionfork_generator_inference", "motionfork_bundle"],
    # Inference does not depend on evaluation or training, and takes options structs (its bundles
    # load through the bundle layer).
    "motionfork_generator_inference": ["motionfork_eval", "motionfork_generator_training",
                                       "motionfork_config", "motionfork_bundle"],
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main(source_dir, build_dir):
    src = os.path.join(source_dir, "src")
    graph = {}  # target -> (files, closure)
    with open(os.path.join(build_dir, "module_graph.tsv")) as f:
        for line in f:
            target, files, closure = line.rstrip("\n").split("\t")
            graph[target] = ([x for x in files.split(",") if x],
                             set(x for x in closure.split(",") if x))
    owners = {}  # folder -> targets with sources there
    for target, (files, _) in graph.items():
        for f in files:
            owners.setdefault(os.path.dirname(f), set()).add(target)
    problems = []
    for a, (_, ca) in graph.items():
        for b in ca:
            if b in graph and a in graph[b][1] and a < b:
                problems.append(f"cycle: {a} and {b} link each other")

    for a, banned in FORBIDDEN.items():
        for b in banned:
            if a in graph and b in graph[a][1]:
                problems.append(f"forbidden link: {a} reaches {b}")

    def allowed(target):
        mine = {target} | graph[target][1]
        return {folder for folder, ts in owners.items() if ts & mine}

    def check(path, folders_ok, who):
        with open(os.path.join(src, path), encoding="utf-8") as f:
            text = f.read()
        for inc in INCLUDE.findall(text):
            header = os.path.normpath(os.path.join(src, inc))
            if not os.path.isfile(header):
                continue  # not a module header (tests' helpers, generated, public API)
            folder = os.path.dirname(os.path.relpath(header, src))
            if folder not in folders_ok:
                problems.append(f"src/{path}: includes \"{inc}\", but {who} links no library of "
                                f"src/{folder}/")

    checked = 0
    for target, (files, _) in graph.items():
        ok = allowed(target)
        for f in files:
            check(f, ok, target)
            checked += 1
    # Headers: what every library that owns their folder may include.
    for folder, ts in owners.items():
        ok = set.intersection(*(allowed(t) for t in ts))
        for name in sorted(os.listdir(os.path.join(src, folder))):
            if name.endswith((".h", ".inc")):
                check(os.path.join(folder, name), ok, " and ".join(sorted(ts)))
                checked += 1
    for p in problems:
        print(p)
    print(f"{checked} files of {len(graph)} libraries checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
