from walk3d.cli import main

main()
