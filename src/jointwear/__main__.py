"""``python -m jointwear ...`` runs the command line."""

from jointwear.cli import main

if __name__ == "__main__":
    main()
