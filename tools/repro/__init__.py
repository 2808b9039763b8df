"""The reproduction of the paper's tables and figures (reproduce.py); installed as pdtrepro."""
