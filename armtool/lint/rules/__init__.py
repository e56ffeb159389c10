"""One module per rule; `armtool.lint.registry` lists them."""
