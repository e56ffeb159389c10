from armtool.cli import main

main()
