"""Command-line interface (placeholder until the predict command lands)."""

def main(argv=None) -> int:
    print("sealeak: no commands yet")
    return 0
