from cutsim.cli import main

main()
