"""Generated code: see derivation/ and manifest.json. Do not edit."""
