#!/usr/bin/env python3
"""Writes a validation split for choosing a training recipe without looking at the test split.

    python3 tools/make_validation_split.py ../shared/data/bandai/split.tsv > val_split.tsv

Keeps only the protocol's training clips: the styles "old" (dataset-1) and "youthful"
(dataset-2) become "test" (held out, like the test split's unseen "elderly" style), the rest
stay "train". The real test clips are left out, so `motionfork train --split val_split.tsv` never
sees them and `motionfork eval --split-file val_split.tsv` scores the held-out styles.
"""
import sys

HELD_OUT_STYLES = ("old", "youthful")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    counts = {"train": 0, "test": 0}
    print("# split\tclip: training clips of %s, styles %s held out as test" % (sys.argv[1], ", ".join(HELD_OUT_STYLES)))
    with open(sys.argv[1]) as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\r\n")
            if not line or line.startswith("#"):
                continue
            fields = line.split("\t")
            if len(fields) != 2:
                sys.exit("%s, line %d: expected 'split<TAB>clip', found %r" % (sys.argv[1], number, line))
            split, clip = fields
            if split != "train":
                continue
            parts = clip.split("_")  # dataset-N_action_style_take.bvh
            style = parts[2] if len(parts) >= 4 else ""
            split = "test" if style in HELD_OUT_STYLES else "train"
            counts[split] += 1
            print("%s\t%s" % (split, clip))
    print("validation split: %d train, %d held-out clips" % (counts["train"], counts["test"]), file=sys.stderr)


if __name__ == "__main__":
    main()
