"""One module per IK solver; `armtool.ik.registry` lists them."""
