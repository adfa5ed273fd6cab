"""A URDF whose every link is heavier: each mass and inertia entry times a factor (the examples'
robot that is not its URDF).
    python3 heavier_urdf.py IN.urdf OUT.urdf FACTOR"""
import re
import sys

source, target, factor = sys.argv[1], sys.argv[2], float(sys.argv[3])
text = open(source).read()
heavier = re.sub(r'\b(value|ixx|ixy|ixz|iyy|iyz|izz)="([-0-9.eE+]+)"',
                 lambda m: f'{m.group(1)}="{float(m.group(2)) * factor!r}"', text)
open(target, "w").write(heavier)
