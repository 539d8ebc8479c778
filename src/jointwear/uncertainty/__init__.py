"""jointwear.uncertainty"""
