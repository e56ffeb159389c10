"""Output formats for lint findings; `armtool.output.registry` lists them."""
