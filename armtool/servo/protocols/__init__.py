"""One module per bus protocol; armtool/servo/registry.py names them."""
