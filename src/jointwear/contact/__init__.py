"""jointwear.contact"""
