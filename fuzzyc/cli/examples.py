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
    folders: dict = {}
    paths = api.examples()
    for path in paths:
        folders.setdefault(path.parent, []).append(path)
    width = max(len(path.name) for path in paths)      # one column of titles for all
    for folder, in_folder in folders.items():
        print(f"{folder}:")
        for path in in_folder:
            print(f"  {path.name:{width}s}  {_title(path)}".rstrip())
    print("copy them with: fuzzyc examples DIR")
    return 0


def _title(path) -> str:
    """A rule file's or scenario's title; nothing for other files."""
    from .. import api
    if path.suffix == ".fz":
        return api.load(path).title
    if path.suffix == ".yaml":
        import yaml
        return str((yaml.safe_load(path.read_text(encoding="utf-8")) or {}).get("title", ""))
    return ""
