"""Turn a motionfork BVH of the Bandai skeleton into one as a user's tool would export it: Mixamo
joint names ("mixamorig:LeftUpLeg"), a finger joint under each hand, an extra root joint turning
the body Z-up ("Armature", as Blender's exports have), and twice the frame rate (frames halfway
between the original ones). Standard library only.

  python3 make_user_rig_bvh.py IN.bvh OUT.bvh
"""
import sys

NAMES = {"Hips": "Hips", "Spine": "Spine1", "Chest": "Spine2", "Neck": "Neck", "Head": "Head"}
for side, word in (("L", "Left"), ("R", "Right")):
    NAMES.update({"UpperLeg_" + side: word + "UpLeg", "LowerLeg_" + side: word + "Leg",
                  "Foot_" + side: word + "Foot", "UpperArm_" + side: word + "Arm",
                  "LowerArm_" + side: word + "ForeArm", "Hand_" + side: word + "Hand"})


def main(src, dst):
    lines = open(src).read().splitlines()
    out, layout, stack, pending = [], [], [], None
    i = 0
    while lines[i].strip() != "MOTION":
        s = lines[i].strip()
        pad = lines[i][: len(lines[i]) - len(lines[i].lstrip())]
        word = s.split()[0] if s else ""
        if word in ("ROOT", "JOINT"):
            name = s.split()[1]
            if word == "ROOT":
                out += ["ROOT Armature", "{", "  OFFSET 0 0 0",
                        "  CHANNELS 3 Xrotation Yrotation Zrotation"]
                layout.append([90.0, 0.0, 0.0])
            out.append("  " + pad + "JOINT mixamorig:" + NAMES[name])
            pending = name
        elif s == "End Site" and stack and stack[-1].startswith("Hand_"):
            finger = "mixamorig:" + NAMES[stack[-1]] + "Index1"
            out.append("  " + pad + "JOINT " + finger)
            pending = "finger"
        elif s == "End Site":
            out.append("  " + pad + s)
            pending = "end"
        elif s == "{":
            stack.append(pending)
            out.append("  " + lines[i])
        elif s == "}":
            stack.pop()
            out.append("  " + lines[i])
        elif word == "OFFSET" and stack[-1] == "finger":
            out.append("  " + lines[i])
            out += ["  " + pad + "CHANNELS 3 Zrotation Xrotation Yrotation", "  " + pad + "End Site",
                    "  " + pad + "{", "  " + pad + "  OFFSET 3 0 0", "  " + pad + "}"]
            layout.append([0.0, 0.0, 0.0])
        elif word == "CHANNELS":
            out.append("  " + lines[i])
            layout.append(int(s.split()[1]))
        elif s == "HIERARCHY":
            out.append(s)
        else:
            out.append("  " + lines[i])
        i += 1
    out.append("}")
    frame_time = float(lines[i + 2].split(":")[1])
    rows = [[float(v) for v in l.split()] for l in lines[i + 3:] if l.strip()]

    def expand(row):
        values, k = [], 0
        for entry in layout:
            if isinstance(entry, int):
                values += row[k:k + entry]
                k += entry
            else:
                values += entry
        return values

    frames = []
    for a, b in zip(rows, rows[1:]):
        frames += [expand(a), expand([(x + y) / 2 for x, y in zip(a, b)])]
    frames.append(expand(rows[-1]))
    out += ["MOTION", "Frames: %d" % len(frames), "Frame Time: %.7f" % (frame_time / 2)]
    out += [" ".join("%.6f" % v for v in f) for f in frames]
    open(dst, "w").write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
