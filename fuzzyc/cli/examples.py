"""`fuzzyc examples [DIR]`: list the shipped rule bases, scenarios and C example, or copy them
into DIR (DIR/rulebases, DIR/scenarios, DIR/c, DIR/gymnasium) to start from after `pip install fuzzyc`."""
from __future__ import annotations


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "examples", help="list the shipped rule bases, scenarios and C example, or copy them",
        description="Without DIR: list the shipped examples with their titles. With DIR: copy "
                    "them into DIR/rulebases, DIR/scenarios, DIR/c and DIR/gymnasium (never "
                    "overwriting without --force).")
    p.add_argument("folder", nargs="?", metavar="DIR", help="folder to copy the examples into")
    p.add_argument("--force", action="store_true",
                   help="replace example files already in DIR (a link there is replaced, not "
                        "followed)")
    p.set_defaults(run=run)


def run(args) -> int:
    from .. import api
    if args.folder:
        from .common import check_output
        check_output(args.folder, folder=True)
        copied = api.copy_examples(args.folder, force=args.force)
        folders = sorted({path.parent.name for path in copied})
        print(f"copied {len(copied)} files into {args.folder}: "
              + ", ".join(f"{name}/" for name in folders))
        print(f"try: fuzzyc verify {args.folder}/rulebases/wedm_three_region.fz")
        return 0
    import yaml
    folders: dict = {}
    for path in api.examples():
        folders.setdefault(path.parent, []).append(path)
    for folder, paths in folders.items():
        print(f"{folder}:")
        for path in paths:
            if path.suffix == ".fz":
                title = api.load(path).title
            elif path.suffix == ".yaml":
                title = (yaml.safe_load(path.read_text(encoding="utf-8")) or {}).get("title", "")
            else:
                title = ""
            print(f"  {path.name:24s} {title}".rstrip())
    print("copy them with: fuzzyc examples DIR")
    return 0
